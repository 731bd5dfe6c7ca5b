#version 450 core
// Radix sort, step 2: the exclusive prefix sum of the whole histogram (one work group): each
// thread sums a run, the 256 run totals are scanned in shared memory, each run is rewritten as
// its exclusive prefix. hist[digit · groups + group] becomes where that group's first key of that
// digit goes.
layout(local_size_x = 256) in;
layout(std430, binding = 20) buffer Histogram { uint hist[]; };
uniform uint u_entries; // 256 · groups
shared uint totals[256];

void main() {
    uint t = gl_LocalInvocationID.x;
    uint run = (u_entries + 255u) / 256u;
    uint begin = min(t * run, u_entries), end = min(begin + run, u_entries);
    uint sum = 0u;
    for (uint i = begin; i < end; ++i)
        sum += hist[i];
    totals[t] = sum;
    barrier();
    // Hillis–Steele inclusive scan of the run totals.
    for (uint step = 1u; step < 256u; step <<= 1u) {
        uint add = t >= step ? totals[t - step] : 0u;
        barrier();
        totals[t] += add;
        barrier();
    }
    uint offset = totals[t] - sum;
    for (uint i = begin; i < end; ++i) {
        uint v = hist[i];
        hist[i] = offset;
        offset += v;
    }
}
