#version 450 core
// Radix sort, step 3: each work group moves its block's keys and values to their places, in
// block order so the sort is stable (which the next digit relies on): one invocation walks the
// block with the group's running offsets per digit. On a CPU rasterizer this is the least work;
// the GPU path's parallelism is across blocks.
layout(local_size_x = 1) in;
layout(std430, binding = 16) readonly buffer KeysIn { uint keysIn[]; };
layout(std430, binding = 17) readonly buffer ValuesIn { uint valuesIn[]; };
layout(std430, binding = 18) writeonly buffer KeysOut { uint keysOut[]; };
layout(std430, binding = 19) writeonly buffer ValuesOut { uint valuesOut[]; };
layout(std430, binding = 20) readonly buffer Histogram { uint hist[]; };
uniform uint u_count;
uniform uint u_shift;
uniform uint u_block;
shared uint offsets[256];

void main() {
    uint g = gl_WorkGroupID.x, groups = gl_NumWorkGroups.x;
    for (uint d = 0u; d < 256u; ++d)
        offsets[d] = hist[d * groups + g];
    uint begin = g * u_block, end = min(begin + u_block, u_count);
    for (uint i = begin; i < end; ++i) {
        uint k = keysIn[i];
        uint d = (k >> u_shift) & 255u;
        uint at = offsets[d]++;
        keysOut[at] = k;
        valuesOut[at] = valuesIn[i];
    }
}
