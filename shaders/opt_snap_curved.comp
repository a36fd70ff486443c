#version 450
// Snaps each vertex that has a curved surface onto it, along the surface's
// normal through the vertex: a sphere (centre, radius), a cylinder (a point
// on its axis, unit axis, radius) or a cone (apex, unit axis into the cone,
// cos and sin of its half-angle) or a plane (a point on it, unit normal), or
// onto the nearest point of a cubic B-spline height field (Gauss-Newton, as
// core/optimizer/height_field_eval.h). Coordinates are about the mesh's centre.
// CPU reference: kernel_snap_curved in core/optimizer/optimizer_kernels.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer V { float v[]; };
layout(std430, binding = 1) readonly buffer VS { int vsurface[]; };
// 3 per surface: (point, kind 0 sphere / 1 cylinder / 2 cone / 3 plane), (axis, radius), (cos, sin, 0, 0);
// a height field (kind 4): (plan origin, 0, 4), (e1, offset into H, 0), (poles along u, along v, 0, 0)
layout(std430, binding = 2) readonly buffer S { vec4 surfaces[]; };
// Per height field from its offset: knots along u (nu + 4), along v (nv + 4), pole heights (u fastest).
layout(std430, binding = 3) readonly buffer H { float heights[]; };
layout(push_constant) uniform P { uint n; } pc;

// The four cubic basis functions of the knots at `at` not vanishing at t
// (clamped into their span) and their derivatives; returns the first one's pole.
int cubic_basis(int at, int poles, float t, out float b[4], out float d[4]) {
  t = clamp(t, heights[at + 3], heights[at + poles]);
  int s = 3;
  while (s < poles - 1 && t >= heights[at + s + 1]) ++s;
  float left[4], right[4], b2[3];
  b[0] = 1.0;
  for (int j = 1; j <= 3; ++j) {
    left[j] = t - heights[at + s + 1 - j];
    right[j] = heights[at + s + j] - t;
    float saved = 0.0;
    for (int r = 0; r < j; ++r) {
      float temp = b[r] / (right[r + 1] + left[j - r]);
      b[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    b[j] = saved;
    if (j == 2) { b2[0] = b[0]; b2[1] = b[1]; b2[2] = b[2]; }
  }
  for (int r = 0; r <= 3; ++r) {
    float dr = 0.0;
    if (r >= 1) dr += 3.0 * b2[r - 1] / (heights[at + s + r] - heights[at + s + r - 3]);
    if (r <= 2) dr -= 3.0 * b2[r] / (heights[at + s + r + 1] - heights[at + s + r - 2]);
    d[r] = dr;
  }
  return s - 3;
}

// Height and its slopes (h, dh/du, dh/dv) at (u, v).
vec3 height_at(int ku, int nu, int kv, int nv, int z, float u, float v) {
  float bu[4], du[4], bv[4], dv[4];
  int iu = cubic_basis(ku, nu, u, bu, du), iv = cubic_basis(kv, nv, v, bv, dv);
  vec3 s = vec3(0.0);
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      float pole = heights[z + (iu + a) + nu * (iv + b)];
      s.x += bu[a] * bv[b] * pole;
      s.y += du[a] * bv[b] * pole;
      s.z += bu[a] * dv[b] * pole;
    }
  return s;
}

vec3 onto_height_field(vec3 p, int k) {
  vec2 o = surfaces[3 * k].xy, e1 = surfaces[3 * k + 1].xy;
  int ku = int(surfaces[3 * k + 1].z), nu = int(surfaces[3 * k + 2].x), nv = int(surfaces[3 * k + 2].y);
  int kv = ku + nu + 4, z = kv + nv + 4;
  float dx = p.x - o.x, dy = p.y - o.y;
  float pu = dx * e1.x + dy * e1.y, pv = dy * e1.x - dx * e1.y;
  float u = pu, w = pv;
  for (int step = 0; step < 6; ++step) {  // kNearestSteps
    u = clamp(u, heights[ku + 3], heights[ku + nu]);
    w = clamp(w, heights[kv + 3], heights[kv + nv]);
    vec3 s = height_at(ku, nu, kv, nv, z, u, w);
    float r = s.x - p.z;
    float gu = (u - pu) + r * s.y, gv = (w - pv) + r * s.z;
    float c = (s.y * gu + s.z * gv) / (1.0 + s.y * s.y + s.z * s.z);
    u -= gu - s.y * c;
    w -= gv - s.z * c;
  }
  u = clamp(u, heights[ku + 3], heights[ku + nu]);
  w = clamp(w, heights[kv + 3], heights[kv + nv]);
  float h = height_at(ku, nu, kv, nv, z, u, w).x;
  return vec3(o.x + u * e1.x - w * e1.y, o.y + u * e1.y + w * e1.x, h);
}

void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  int k = vsurface[i];
  if (k < 0) return;
  vec3 p = vec3(v[3u * i], v[3u * i + 1u], v[3u * i + 2u]);
  vec3 c = surfaces[3 * k].xyz;
  float kind = surfaces[3 * k].w;
  vec3 a = surfaces[3 * k + 1].xyz;
  float r = surfaces[3 * k + 1].w;
  vec3 q = p - c;
  if (kind == 4.0) {
    p = onto_height_field(p, k);
  } else if (kind == 3.0) {
    p = p - a * dot(q, a);
  } else if (kind == 0.0) {
    float len = sqrt(dot(q, q));
    if (len <= 0.0) return;
    p = c + q * (r / len);
  } else {
    float t = dot(q, a);
    vec3 radial = q - a * t;
    float rho = sqrt(dot(radial, radial));
    if (rho <= 0.0) return;
    vec3 e = radial * (1.0 / rho);
    if (kind == 1.0) {
      p = c + a * t + e * r;
    } else {
      vec3 g = a * surfaces[3 * k + 2].x + e * surfaces[3 * k + 2].y;  // the generator through p
      p = c + g * max(dot(q, g), 0.0);
    }
  }
  v[3u * i] = p.x;
  v[3u * i + 1u] = p.y;
  v[3u * i + 2u] = p.z;
}
