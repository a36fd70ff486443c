#version 450
// Snaps each vertex that has a curved surface onto it, along the surface's
// normal through the vertex: a sphere (centre, radius), a cylinder (a point
// on its axis, unit axis, radius) or a cone (apex, unit axis into the cone,
// cos and sin of its half-angle) or a plane (a point on it, unit normal).
// Coordinates are about the mesh's centre.
// CPU reference: kernel_snap_curved in core/optimizer/optimizer_kernels.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer V { float v[]; };
layout(std430, binding = 1) readonly buffer VS { int vsurface[]; };
// 3 per surface: (point, kind 0 sphere / 1 cylinder / 2 cone / 3 plane), (axis, radius), (cos, sin, 0, 0)
layout(std430, binding = 2) readonly buffer S { vec4 surfaces[]; };
layout(push_constant) uniform P { uint n; } pc;
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
  if (kind == 3.0) {
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
