#version 450
// Applies the rigid transform of each vertex's normal cluster: p' = R p + t.
// CPU reference: transform_cpu in core/optimizer_kernels.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer V { float v[]; };
layout(std430, binding = 1) readonly buffer C { int vcluster[]; };
layout(std430, binding = 2) readonly buffer T { float xf[]; };  // 12 per cluster: R row-major, t
layout(push_constant) uniform P { uint n; } pc;
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  int c = vcluster[i];
  if (c < 0) return;
  uint b = 12u * uint(c);
  vec3 p = vec3(v[3u * i], v[3u * i + 1u], v[3u * i + 2u]);
  vec3 q;
  q.x = xf[b + 0u] * p.x + xf[b + 1u] * p.y + xf[b + 2u] * p.z + xf[b + 9u];
  q.y = xf[b + 3u] * p.x + xf[b + 4u] * p.y + xf[b + 5u] * p.z + xf[b + 10u];
  q.z = xf[b + 6u] * p.x + xf[b + 7u] * p.y + xf[b + 8u] * p.z + xf[b + 11u];
  v[3u * i] = q.x;
  v[3u * i + 1u] = q.y;
  v[3u * i + 2u] = q.z;
}
