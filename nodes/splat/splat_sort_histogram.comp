#version 450 core
// Radix sort, step 1 of 3 per 8-bit digit: each work group counts the digits of its block of
// u_block keys into its column of the histogram (digit-major: hist[digit · groups + group]).
layout(local_size_x = 256) in;
layout(std430, binding = 16) readonly buffer Keys { uint keys[]; };
layout(std430, binding = 20) writeonly buffer Histogram { uint hist[]; };
uniform uint u_count;
uniform uint u_shift;
uniform uint u_block;
shared uint counts[256];

void main() {
    uint t = gl_LocalInvocationID.x, g = gl_WorkGroupID.x;
    counts[t] = 0u;
    barrier();
    uint begin = g * u_block, end = min(begin + u_block, u_count);
    for (uint i = begin + t; i < end; i += 256u)
        atomicAdd(counts[(keys[i] >> u_shift) & 255u], 1u);
    barrier();
    hist[t * gl_NumWorkGroups.x + g] = counts[t];
}
