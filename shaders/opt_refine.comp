#version 450
// One dispatch over a task list: the first n_junction tasks snap their vertex
// onto its intersection line, the rest fall through to surface work
// (projection onto the vertex's plane). Every task owns one distinct vertex,
// so no locks are needed. CPU reference: refine_cpu in core/optimizer_kernels.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer V { float v[]; };
layout(std430, binding = 1) readonly buffer A { uint tasks[]; };
layout(std430, binding = 2) readonly buffer VP { int vplane[]; };
layout(std430, binding = 3) readonly buffer VL { int vline[]; };
layout(std430, binding = 4) readonly buffer PL { vec4 planes[]; };
layout(std430, binding = 5) readonly buffer LN { vec4 lines[]; };
layout(push_constant) uniform P { uint m; uint n_junction; } pc;
void main() {
  uint t = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (t >= pc.m) return;
  uint i = tasks[t];
  vec3 p = vec3(v[3u * i], v[3u * i + 1u], v[3u * i + 2u]);
  if (t < pc.n_junction) {
    int l = vline[i];
    if (l < 0) return;
    vec3 o = lines[2 * l].xyz;
    vec3 dir = lines[2 * l + 1].xyz;
    p = o + dot(p - o, dir) * dir;
  } else {
    int k = vplane[i];
    if (k < 0) return;
    p = p - (dot(planes[k].xyz, p) + planes[k].w) * planes[k].xyz;
  }
  v[3u * i] = p.x;
  v[3u * i + 1u] = p.y;
  v[3u * i + 2u] = p.z;
}
