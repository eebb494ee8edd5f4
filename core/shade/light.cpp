// Maya's light falloff over a batch of samples (reference/nodes.md §3). Every formula is evaluated
// in double precision per sample and stored as float; a sample sitting exactly on a point, spot or
// ambient light's position gets a finite answer (the light is taken to shine along the normal).
#include "core/shade/light.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::shade {

namespace {

// Unit direction from the sample toward `position`, and the distance. At the light's position the
// direction is undefined: the sample's normal stands in for it (distance 0).
inline glm::dvec3 towardLight(const glm::dvec3& position, const ShadingBatch& b, int i, double& distance) {
    const glm::dvec3 d = position - glm::dvec3(b.px[i], b.py[i], b.pz[i]);
    distance = glm::length(d);
    if (distance > 1e-12 && std::isfinite(distance)) return d / distance;
    distance = 0.0;
    const glm::dvec3 n(b.nx[i], b.ny[i], b.nz[i]);
    const double len = glm::length(n);
    return len > 1e-12 && std::isfinite(len) ? n / len : glm::dvec3(0.0, 0.0, 1.0);
}

// Decay (nodes.md §3): none, 1/d, 1/d², 1/d³, with "no effect at distances less than 1 unit".
inline double decay(int rate, double distance) {
    if (rate <= 0) return 1.0;
    const double d = std::max(distance, 1.0);
    switch (rate) {
        case 1: return 1.0 / d;
        case 2: return 1.0 / (d * d);
        default: return 1.0 / (d * d * d);
    }
}

// Spot cone, penumbra and dropoff at angle `theta` (radians) from the spot's axis, cosTheta its cosine.
inline double spotFactor(const Light& light, double theta, double cosTheta) {
    const double half = 0.5 * double(light.coneAngle);
    const double p = double(light.penumbraAngle);
    // Positive penumbra: full inside the cone, fading to 0 at half + p. Negative: full inside
    // half + p, fading to 0 at the cone edge (nodes.md: cone 50, penumbra −10 fades 15°→25°).
    const double inner = p >= 0.0 ? half : half + p;
    const double outer = p >= 0.0 ? half + p : half;
    double f;
    if (theta <= inner) f = 1.0;
    else if (theta >= outer) f = 0.0;
    else f = (outer - theta) / (outer - inner);
    if (f <= 0.0) return 0.0;
    // Dropoff: cos(θ)^dropoff (the common reading, unverified in nodes.md); dropoff 0 gives 1.
    if (light.dropoff > 0.0f) f *= std::pow(std::max(cosTheta, 0.0), double(light.dropoff));
    return f;
}

inline void store(LightSamples& out, int i, const glm::dvec3& l, const glm::dvec3& intensity) {
    out.lx[i] = float(l.x);
    out.ly[i] = float(l.y);
    out.lz[i] = float(l.z);
    out.ir[i] = float(intensity.x);
    out.ig[i] = float(intensity.y);
    out.ib[i] = float(intensity.z);
}

}  // namespace

void illuminate(const Light& light, const ShadingBatch& batch, LightSamples& out) {
    const int count = std::clamp(batch.count, 0, kBatchSize);
    const glm::dvec3 color(light.color);
    out.ambient = light.type == LightType::Ambient;
    out.diffuse = !out.ambient && light.emitDiffuse;
    out.specular = !out.ambient && light.emitSpecular;

    switch (light.type) {
        case LightType::Ambient: {
            const double shade = double(light.ambientShade);
            for (int i = 0; i < count; ++i) {
                double d = 0.0;
                const glm::dvec3 l = towardLight(light.position, batch, i, d);
                const double nl = double(batch.nx[i]) * l.x + double(batch.ny[i]) * l.y + double(batch.nz[i]) * l.z;
                // nodes.md §3 (formula unverified): I·((1 − as) + as·max(0, N·L)).
                const double k = (1.0 - shade) + shade * (std::isfinite(nl) ? std::max(nl, 0.0) : 0.0);
                store(out, i, l, color * k);
            }
            break;
        }
        case LightType::Directional: {
            double len = glm::length(light.direction);
            const glm::dvec3 l = len > 1e-12 && std::isfinite(len) ? -light.direction / len : glm::dvec3(0, 0, 1);
            for (int i = 0; i < count; ++i) store(out, i, l, color);
            break;
        }
        case LightType::Point: {
            for (int i = 0; i < count; ++i) {
                double d = 0.0;
                const glm::dvec3 l = towardLight(light.position, batch, i, d);
                store(out, i, l, color * decay(light.decayRate, d));
            }
            break;
        }
        case LightType::Spot: {
            double len = glm::length(light.direction);
            const glm::dvec3 axis = len > 1e-12 && std::isfinite(len) ? light.direction / len : glm::dvec3(0, 0, -1);
            for (int i = 0; i < count; ++i) {
                double d = 0.0;
                const glm::dvec3 l = towardLight(light.position, batch, i, d);
                // The angle between the axis and (P − position) = −l; on the light itself, the axis.
                const double cosTheta = d > 0.0 ? std::clamp(-glm::dot(axis, l), -1.0, 1.0) : 1.0;
                const double theta = std::acos(cosTheta);
                const double f = spotFactor(light, theta, cosTheta) * decay(light.decayRate, d);
                store(out, i, l, color * f);
            }
            break;
        }
    }
}

Light transformed(const Light& light, const glm::dmat4& m) {
    Light out = light;
    const glm::dvec4 p = m * glm::dvec4(light.position, 1.0);
    if (std::abs(p.w) > 1e-300) out.position = glm::dvec3(p) / p.w;
    const glm::dvec3 d = glm::dmat3(m) * light.direction;
    const double len = glm::length(d);
    if (len > 1e-12 && std::isfinite(len)) out.direction = d / len;
    return out;
}

Light defaultLight(const glm::dvec3& viewDirection) {
    Light l;
    l.type = LightType::Directional;
    l.name = "defaultLight";
    l.shape = ~0u;
    l.color = glm::vec3(1.0f);
    const double len = glm::length(viewDirection);
    l.direction = len > 1e-12 && std::isfinite(len) ? viewDirection / len : glm::dvec3(0.0, 0.0, -1.0);
    l.position = glm::dvec3(0.0);
    return l;
}

}  // namespace pushpin::shade
