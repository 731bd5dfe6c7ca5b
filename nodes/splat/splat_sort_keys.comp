#version 450 core
// The sort's keys: each splat's view depth (metres in front of the eye) as an unsigned integer
// of the same order, inverted so that an ascending sort puts the farthest first; values are the
// splat indices.
layout(local_size_x = 256) in;
layout(std430, binding = 13) readonly buffer SplatData { vec4 splats[]; };
layout(std430, binding = 16) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 17) writeonly buffer Values { uint values[]; };
uniform uint u_count;
uniform vec4 u_depthRow; // row 2 of the model-view matrix: view z = dot(row, (p, 1))

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    float depth = -dot(u_depthRow, vec4(splats[3u * i].xyz, 1.0));
    uint u = floatBitsToUint(depth);
    uint sortable = (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
    keys[i] = ~sortable;
    values[i] = i;
}
