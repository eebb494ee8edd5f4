// Maya's surface materials as batch kernels: lambert, phong, blinn, phongE and surfaceShader
// (reference/nodes.md §4). Maya publishes no exact equations; the models below follow the devkit
// example shaders nodes.md quotes, and say where they are pushpin's reading.
//
// Common to every lit material, per sample (all vectors in camera space):
//   N = the `normalCamera` input (the renderer's normal unless connected, e.g. from a bump),
//       renormalised; V = −rayDirection (toward the eye);
//   A = ambientColor + Σ_ambient lights I_l                     (where ambientColor enters is unverified)
//   D = diffuse · Σ_diffuse lights I_l · max(0, N·L)
//   outColor = color · (A + D) · (1 − transparency) + incandescence + specularColor · S
//   outTransparency = transparency
// where S (specular, not scaled by transparency) sums over lights with the specular flag where
// N·L > 0:
//   phong  (devkit phongShader):  R = 2N(N·L) − L,  S += I_l · max(0, R·V)^cosinePower
//   blinn  (Blinn 1977 microfacet model; that Maya uses exactly this is unverified):
//          H = normalize(L + V), c = eccentricity (c = 0: no highlight),
//          D_b = (c² / ((N·H)²(c² − 1) + 1))²,
//          G = min(1, 2(N·H)(N·V)/(V·H), 2(N·H)(N·L)/(V·H)),
//          F = sro + (1 − sro)(1 − V·H)^5 with sro = specularRollOff,
//          S += I_l · D_b · G · F / max(N·V, 1e-4)
//   phongE (no published formula; pushpin's approximation): H = normalize(L + V),
//          e = 1 / max(roughness² · highlightSize, 1e-4), S += I_l · max(0, N·H)^e,
//          and the highlight colour is specularColor · whiteness.
// An ambient light's shade term uses the renderer's normal (illuminate() reads the batch), also
// under a connected normalCamera.
#include "core/shade/node_library.h"

#include <algorithm>
#include <cmath>

namespace pushpin::shade::detail {

namespace {

// Input channel layout shared by the lambert family (ports in declaration order).
enum : uint32_t {
    kColor = 0,
    kTransparency = 3,
    kAmbientColor = 6,
    kIncandescence = 9,
    kDiffuse = 12,
    kNormal = 13,
    kSpecularColor = 16,  // reflect and derived types
    kExtra = 19,          // first type-specific input
};
// Output layout: outColor 0..2, outTransparency 3..5.

enum class Specular { None, Phong, Blinn, PhongE };

template <Specular kModel>
void materialKernel(const KernelContext& ctx, const CompiledNode& node) {
    const int n = ctx.count;
    const ShadingBatch& b = ctx.batch;
    // Working arrays on the stack: unit N, V, and the ambient / diffuse / specular sums.
    float nx[kBatchSize], ny[kBatchSize], nz[kBatchSize];
    float ar[kBatchSize], ag[kBatchSize], ab[kBatchSize];
    float dr[kBatchSize], dg[kBatchSize], db[kBatchSize];
    float sr[kBatchSize], sg[kBatchSize], sb[kBatchSize];

    const Chan inN[3] = {ctx.in(node, kNormal), ctx.in(node, kNormal + 1), ctx.in(node, kNormal + 2)};
    const Chan amb[3] = {ctx.in(node, kAmbientColor), ctx.in(node, kAmbientColor + 1), ctx.in(node, kAmbientColor + 2)};
    for (int i = 0; i < n; ++i) {
        float x = inN[0][i], y = inN[1][i], z = inN[2][i];
        const float len = std::sqrt(x * x + y * y + z * z);
        if (len > 1e-20f && std::isfinite(len)) {
            x /= len, y /= len, z /= len;
        } else {  // a degenerate connected normal: fall back to the renderer's
            x = b.nx[i], y = b.ny[i], z = b.nz[i];
        }
        nx[i] = x, ny[i] = y, nz[i] = z;
        ar[i] = amb[0][i], ag[i] = amb[1][i], ab[i] = amb[2][i];
        dr[i] = dg[i] = db[i] = 0.0f;
        sr[i] = sg[i] = sb[i] = 0.0f;
    }

    // Type-specific specular parameters.
    Chan p0{}, p1{};
    if constexpr (kModel != Specular::None) {
        p0 = ctx.in(node, kExtra);
        if constexpr (kModel != Specular::Phong) p1 = ctx.in(node, kExtra + 1);
    }

    LightSamples& ls = ctx.lightSamples;
    for (const Light& light : ctx.lights) {
        illuminate(light, b, ls);
        if (ls.ambient) {
            for (int i = 0; i < n; ++i) ar[i] += ls.ir[i], ag[i] += ls.ig[i], ab[i] += ls.ib[i];
            continue;
        }
        if (ls.diffuse) {
            for (int i = 0; i < n; ++i) {
                const float k = std::max(0.0f, nx[i] * ls.lx[i] + ny[i] * ls.ly[i] + nz[i] * ls.lz[i]);
                dr[i] += ls.ir[i] * k, dg[i] += ls.ig[i] * k, db[i] += ls.ib[i] * k;
            }
        }
        if constexpr (kModel != Specular::None) {
            if (!ls.specular) continue;
            for (int i = 0; i < n; ++i) {
                const float lx = ls.lx[i], ly = ls.ly[i], lz = ls.lz[i];
                const float nl = nx[i] * lx + ny[i] * ly + nz[i] * lz;
                if (!(nl > 0.0f)) continue;
                const float vx = -b.rx[i], vy = -b.ry[i], vz = -b.rz[i];
                float s = 0.0f;
                if constexpr (kModel == Specular::Phong) {
                    const float rx = 2.0f * nl * nx[i] - lx, ry = 2.0f * nl * ny[i] - ly, rz = 2.0f * nl * nz[i] - lz;
                    const float rv = rx * vx + ry * vy + rz * vz;
                    if (rv > 0.0f) s = std::pow(rv, p0[i]);
                } else {
                    float hx = lx + vx, hy = ly + vy, hz = lz + vz;
                    const float hl = std::sqrt(hx * hx + hy * hy + hz * hz);
                    if (!(hl > 1e-6f)) continue;  // L opposite V: no half vector
                    hx /= hl, hy /= hl, hz /= hl;
                    const float nh = std::max(0.0f, nx[i] * hx + ny[i] * hy + nz[i] * hz);
                    if constexpr (kModel == Specular::Blinn) {
                        const float c = p0[i];
                        if (!(c > 0.0f)) continue;  // eccentricity 0: no highlight
                        const float c2 = c * c;
                        const float denom = nh * nh * (c2 - 1.0f) + 1.0f;
                        if (!(denom > 1e-12f)) continue;
                        const float dq = c2 / denom;
                        const float distribution = dq * dq;
                        const float nv = nx[i] * vx + ny[i] * vy + nz[i] * vz;
                        const float vh = std::max(vx * hx + vy * hy + vz * hz, 1e-6f);
                        const float g = std::clamp(std::min(2.0f * nh * nv / vh, 2.0f * nh * nl / vh), 0.0f, 1.0f);
                        const float sro = p1[i];
                        const float m = 1.0f - vh;
                        const float m2 = m * m;
                        const float fresnel = sro + (1.0f - sro) * m2 * m2 * m;
                        s = distribution * g * fresnel / std::max(nv, 1e-4f);
                    } else {  // PhongE
                        const float rough = p0[i], size = p1[i];
                        const float e = 1.0f / std::max(rough * rough * size, 1e-4f);
                        s = nh > 0.0f ? std::pow(nh, e) : 0.0f;
                    }
                }
                if (!std::isfinite(s)) continue;
                sr[i] += ls.ir[i] * s, sg[i] += ls.ig[i] * s, sb[i] += ls.ib[i] * s;
            }
        }
    }

    // outColor and outTransparency.
    const Chan diffuse = ctx.in(node, kDiffuse);
    float* out[6];
    for (uint32_t k = 0; k < 6; ++k) out[k] = ctx.out(node, k);
    const float* acc[3] = {ar, ag, ab};
    const float* dif[3] = {dr, dg, db};
    const float* spe[3] = {sr, sg, sb};
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan color = ctx.in(node, kColor + c);
        const Chan transparency = ctx.in(node, kTransparency + c);
        const Chan incandescence = ctx.in(node, kIncandescence + c);
        float* oc = out[c];
        float* ot = out[3 + c];
        for (int i = 0; i < n; ++i) {
            const float t = transparency[i];
            oc[i] = color[i] * (acc[c][i] + diffuse[i] * dif[c][i]) * (1.0f - t) + incandescence[i];
            ot[i] = t;
        }
        if constexpr (kModel != Specular::None) {
            const Chan specular = ctx.in(node, kSpecularColor + c);
            if constexpr (kModel == Specular::PhongE) {
                const Chan whiteness = ctx.in(node, kExtra + 2 + c);
                for (int i = 0; i < n; ++i) oc[i] += specular[i] * whiteness[i] * spe[c][i];
            } else {
                for (int i = 0; i < n; ++i) oc[i] += specular[i] * spe[c][i];
            }
        }
    }
}

// Ports of lambert (in the layout of the enum above) and its outputs.
NodeType lambertType(const char* name, Kernel kernel) {
    NodeType t;
    t.name = name;
    t.inputs = {colorPort("color", "c", 0.5f, 0.5f, 0.5f),
                colorPort("transparency", "it", 0, 0, 0),
                colorPort("ambientColor", "ambc", 0, 0, 0),
                colorPort("incandescence", "ic", 0, 0, 0),
                scalarPort("diffuse", "dc", 0.8f),
                rendererPort("normalCamera", "n")};
    t.outputs = {colorPort("outColor", "oc", 0, 0, 0), colorPort("outTransparency", "ot", 0, 0, 0)};
    t.kernel = kernel;
    t.transparencyInput = 1;
    return t;
}

NodeType reflectType(const char* name, Kernel kernel) {
    NodeType t = lambertType(name, kernel);
    t.inputs.push_back(colorPort("specularColor", "sc", 0.5f, 0.5f, 0.5f));
    return t;
}

}  // namespace

void addMaterialTypes(std::vector<NodeType>& types) {
    types.push_back(lambertType("lambert", &materialKernel<Specular::None>));

    NodeType phong = reflectType("phong", &materialKernel<Specular::Phong>);
    phong.inputs.push_back(scalarPort("cosinePower", "cp", 20.0f));
    types.push_back(std::move(phong));

    NodeType blinn = reflectType("blinn", &materialKernel<Specular::Blinn>);
    blinn.inputs.push_back(scalarPort("eccentricity", "ec", 0.3f));
    blinn.inputs.push_back(scalarPort("specularRollOff", "sro", 0.7f));
    types.push_back(std::move(blinn));

    NodeType phongE = reflectType("phongE", &materialKernel<Specular::PhongE>);
    phongE.inputs.push_back(scalarPort("roughness", "rn", 0.5f));
    phongE.inputs.push_back(scalarPort("highlightSize", "hls", 0.5f));
    phongE.inputs.push_back(colorPort("whiteness", "wn", 0.5f, 0.5f, 0.5f));
    types.push_back(std::move(phongE));

    // surfaceShader: unlit; its outColor / outTransparency are inputs passed straight through.
    NodeType surface;
    surface.name = "surfaceShader";
    surface.inputs = {colorPort("outColor", "oc", 0, 0, 0), colorPort("outTransparency", "ot", 0, 0, 0)};
    surface.outputs = surface.inputs;
    surface.outputs[0].aliasOf = 0;
    surface.outputs[1].aliasOf = 1;
    surface.transparencyInput = 1;
    types.push_back(std::move(surface));
}

}  // namespace pushpin::shade::detail
