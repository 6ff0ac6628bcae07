// Occlusion textures, summed-area table (Crow 1984; compared in Eisemann & Décoret 2006 §3.2):
// S(i, j) = Σ slices over [0, i) × [0, j), i, j in [0, R], in 32-bit integers per channel (exact:
// 0/1 texels sum to at most R² = 2^20 at R = 1024). Two passes, one invocation per line (layer =
// the target): step 0 sums each row into S(·, j + 1), step 1 sums the columns in place.
#include "lib/Bindings.h"

layout(local_size_x = 64) in;

layout(binding = IMAGE_OCCLUSION_SRC, rgba8) uniform readonly image2DArray iSlices;
layout(binding = IMAGE_OCCLUSION_DST, rgba32ui) uniform uimage2DArray iSat;
layout(location = UNIFORM_PREFILTER_STEP) uniform int uStep;

void main() {
    int R = imageSize(iSlices).x;
    int line = int(gl_GlobalInvocationID.x);
    int t = int(gl_GlobalInvocationID.y);
    uvec4 sum = uvec4(0u);
    if (uStep == 0) {
        if (line >= R) return;
        imageStore(iSat, ivec3(0, line + 1, t), sum);
        for (int x = 0; x < R; ++x) {
            sum += uvec4(round(imageLoad(iSlices, ivec3(x, line, t))));
            imageStore(iSat, ivec3(x + 1, line + 1, t), sum);
        }
    } else {
        if (line > R) return;
        imageStore(iSat, ivec3(line, 0, t), sum);
        for (int y = 1; y <= R; ++y) {
            sum += imageLoad(iSat, ivec3(line, y, t));
            imageStore(iSat, ivec3(line, y, t), sum);
        }
    }
}
