#version 450
// Per-vertex energy terms: weighted squared distance to the vertex's plane
// (fitness) and squared distance to its intersection line (junction).
// CPU reference: energy_terms_cpu in core/optimizer_kernels.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer V { float v[]; };
layout(std430, binding = 1) readonly buffer VP { int vplane[]; };
layout(std430, binding = 2) readonly buffer VL { int vline[]; };
layout(std430, binding = 3) readonly buffer PL { vec4 planes[]; };
layout(std430, binding = 4) readonly buffer LN { vec4 lines[]; };
layout(std430, binding = 5) readonly buffer W { float w[]; };
layout(std430, binding = 6) writeonly buffer O { float terms[]; };
layout(push_constant) uniform P { uint n; } pc;
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  vec3 p = vec3(v[3u * i], v[3u * i + 1u], v[3u * i + 2u]);
  float fit = 0.0, junc = 0.0;
  int k = vplane[i];
  if (k >= 0) {
    float d = dot(planes[k].xyz, p) + planes[k].w;
    fit = w[i] * d * d;
  }
  int l = vline[i];
  if (l >= 0) {
    vec3 q = p - lines[2 * l].xyz;
    vec3 dir = lines[2 * l + 1].xyz;
    vec3 r = q - dot(q, dir) * dir;
    junc = dot(r, r);
  }
  terms[2u * i] = fit;
  terms[2u * i + 1u] = junc;
}
