#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Data { float v[]; };
layout(push_constant) uniform P { uint n; float s; } pc;
void main() { uint i = gl_GlobalInvocationID.x; if (i < pc.n) v[i] *= pc.s; }
