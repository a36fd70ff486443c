#version 450
// Flags the triangles a viewpoint needs: centroid inside the view frustum,
// front-facing, and some vertex farther than `threshold` from its plane.
// CPU reference: view_select_cpu in core/optimizer_kernels.cpp.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer V { float v[]; };
layout(std430, binding = 1) readonly buffer T { uint tri[]; };
layout(std430, binding = 2) readonly buffer TP { int tplane[]; };
layout(std430, binding = 3) readonly buffer PL { vec4 planes[]; };
layout(std430, binding = 4) writeonly buffer F { uint flag[]; };
layout(push_constant) uniform P {
  mat4 view_proj;
  vec4 eye;
  uint n;
  float threshold;
} pc;
vec3 vert(uint k) { return vec3(v[3u * k], v[3u * k + 1u], v[3u * k + 2u]); }
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  uint f = 0u;
  int k = tplane[i];
  if (k >= 0) {
    vec3 a = vert(tri[3u * i]), b = vert(tri[3u * i + 1u]), c = vert(tri[3u * i + 2u]);
    vec3 m = (a + b + c) / 3.0;
    vec4 clip = pc.view_proj * vec4(m, 1.0);
    bool inside = clip.w > 0.0 && abs(clip.x) <= clip.w && abs(clip.y) <= clip.w &&
                  abs(clip.z) <= clip.w;
    bool front = dot(cross(b - a, c - a), pc.eye.xyz - m) > 0.0;
    vec4 pl = planes[k];
    float dev = max(abs(dot(pl.xyz, a) + pl.w),
                    max(abs(dot(pl.xyz, b) + pl.w), abs(dot(pl.xyz, c) + pl.w)));
    if (inside && front && dev > pc.threshold) f = 1u;
  }
  flag[i] = f;
}
