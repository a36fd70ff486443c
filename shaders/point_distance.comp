#version 450
// Unsigned distance from each point to the nearest triangle, searched ring by
// ring in a uniform grid over the triangles (cells of size h). A ring r+1 cell
// is at least r*h away, so the search stops once best <= r*h; or once it is
// farther than `cap`, the distance then reported as infinity.
// CPU reference: point_distance_cpu in core/mesh_distance.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer PT { float pts[]; };
layout(std430, binding = 1) readonly buffer TR { float tv[]; };  // 9 floats per triangle
layout(std430, binding = 2) readonly buffer CS { uint cell_start[]; };
layout(std430, binding = 3) readonly buffer CT { uint cell_tris[]; };
layout(std430, binding = 4) writeonly buffer O { float dist[]; };
layout(push_constant) uniform P {
  float ox, oy, oz, h;
  int nx, ny, nz;
  uint np;
  float cap;
} pc;

// Squared distance from p to triangle abc (Ericson, Real-Time Collision Detection 5.1.5).
float tri_dist2(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  vec3 q;
  if (d1 <= 0.0 && d2 <= 0.0) { q = a; }
  else {
    vec3 bp = p - b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { q = b; }
    else {
      float vc = d1 * d4 - d3 * d2;
      if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) { q = a + (d1 / (d1 - d3)) * ab; }
      else {
        vec3 cp = p - c;
        float d5 = dot(ab, cp), d6 = dot(ac, cp);
        if (d6 >= 0.0 && d5 <= d6) { q = c; }
        else {
          float vb = d5 * d2 - d1 * d6;
          if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) { q = a + (d2 / (d2 - d6)) * ac; }
          else {
            float va = d3 * d6 - d5 * d4;
            if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
              q = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
            } else {
              float denom = 1.0 / (va + vb + vc);
              q = a + ab * (vb * denom) + ac * (vc * denom);
            }
          }
        }
      }
    }
  }
  vec3 r = p - q;
  return dot(r, r);
}

void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (i >= pc.np) return;
  vec3 p = vec3(pts[3u * i], pts[3u * i + 1u], pts[3u * i + 2u]);
  ivec3 n = ivec3(pc.nx, pc.ny, pc.nz);
  ivec3 c = clamp(ivec3(floor((p - vec3(pc.ox, pc.oy, pc.oz)) / pc.h)), ivec3(0), n - 1);
  int max_r = max(n.x, max(n.y, n.z));
  if (pc.cap < 1.0e30) max_r = min(max_r, int(ceil(pc.cap / pc.h)) + 1);
  float best = 3.0e38;
  for (int r = 0; r <= max_r; ++r) {
    ivec3 lo = max(c - r, ivec3(0)), hi = min(c + r, n - 1);
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          // only the shell of the ring: inner cells were visited before
          if (max(abs(x - c.x), max(abs(y - c.y), abs(z - c.z))) != r) continue;
          uint cell = uint((z * n.y + y) * n.x + x);
          for (uint k = cell_start[cell]; k < cell_start[cell + 1u]; ++k) {
            uint t = 9u * cell_tris[k];
            float d2 = tri_dist2(p, vec3(tv[t], tv[t + 1u], tv[t + 2u]),
                                 vec3(tv[t + 3u], tv[t + 4u], tv[t + 5u]),
                                 vec3(tv[t + 6u], tv[t + 7u], tv[t + 8u]));
            best = min(best, d2);
          }
        }
    float reach = float(r) * pc.h;
    if (best <= reach * reach) break;
  }
  dist[i] = best > pc.cap * pc.cap ? uintBitsToFloat(0x7F800000u) : sqrt(best);
}
