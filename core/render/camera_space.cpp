#include "core/render/camera_space.h"

namespace pushpin::render {

int clipNear(const glm::dvec3 in[3], double nearZ, glm::dvec3 out[4]) {
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3& a = in[i];
        const glm::dvec3& b = in[(i + 1) % 3];
        const bool aIn = a.z <= nearZ, bIn = b.z <= nearZ;
        if (aIn) out[n++] = a;
        if (aIn != bIn) {
            const double t = (nearZ - a.z) / (b.z - a.z);
            out[n++] = a + (b - a) * t;
        }
    }
    return n;
}

}  // namespace pushpin::render
