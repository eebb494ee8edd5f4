// core/shade/shading_batch.h: the struct-of-arrays a shading network evaluates over (DESIGN.md 6d,
// STYLE.md §24): up to kBatchSize shading samples of one object under one shading group, each
// with the renderer-provided values Maya passes to shading nodes (reference/nodes.md §8:
// pointCamera, normalCamera, rayDirection, uvCoord, facingRatio …), and the result arrays.
// Plain data; one batch per thread, reused. All vectors are in Maya's camera space (+X right,
// +Y up, the camera looking down −Z), unit length where said so.
#pragma once

#include <cstdint>

namespace pushpin::shade {

constexpr int kBatchSize = 64;

struct ShadingBatch {
    int count = 0;  // samples in use, 0..kBatchSize

    float px[kBatchSize], py[kBatchSize], pz[kBatchSize];  // pointCamera
    // normalCamera: unit shading normal (interpolated, smoothShading), turned to face the eye
    // when the surface is double-sided and seen from its back (then flipped[i] = 1).
    float nx[kBatchSize], ny[kBatchSize], nz[kBatchSize];
    float gx[kBatchSize], gy[kBatchSize], gz[kBatchSize];  // unit geometric normal, same side as normalCamera
    float rx[kBatchSize], ry[kBatchSize], rz[kBatchSize];  // rayDirection: unit, eye → point
    float u[kBatchSize], v[kBatchSize];                    // uvCoord (current UV set; 0 where unmapped)
    float wx[kBatchSize], wy[kBatchSize], wz[kBatchSize];  // pointWorld
    float ox[kBatchSize], oy[kBatchSize], oz[kBatchSize];  // pointObj
    // tangentUCamera / tangentVCamera: dP/du, dP/dv (camera space, not normalised; 0 without UVs)
    float tux[kBatchSize], tuy[kBatchSize], tuz[kBatchSize];
    float tvx[kBatchSize], tvy[kBatchSize], tvz[kBatchSize];
    float pixelX[kBatchSize], pixelY[kBatchSize];          // pixelCenter (raster)
    uint8_t flipped[kBatchSize];                           // flippedNormal

    uint32_t objectId = 0;  // uniform over the batch
};

// What a network returns per sample: the shading group's outColor and outTransparency.
struct ShadingResult {
    float cr[kBatchSize], cg[kBatchSize], cb[kBatchSize];
    float tr[kBatchSize], tg[kBatchSize], tb[kBatchSize];
};

}  // namespace pushpin::shade
