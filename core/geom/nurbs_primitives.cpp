// core/geom/nurbs_primitives.cpp: the NURBS primitives of Maya's creator nodes. Shapes are built in
// a frame whose axis is +Y (the layout checked against Maya's files) and then moved to the requested
// axis and pivot. See nurbs_primitives.h for the construction and what is verified.
#include "core/geom/nurbs_primitives.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::geom {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

bool fail(std::string* error, const std::string& msg) {
    if (error) *error = msg;
    return false;
}

std::nullopt_t failWith(std::string* error, const std::string& msg) {
    if (error) *error = msg;
    return std::nullopt;
}

bool isFullTurn(double sweep) { return std::abs(std::abs(sweep) - kTwoPi) < 1e-9 || std::abs(sweep) > kTwoPi; }

// Shortest rotation taking unit vector a to unit vector b (Rodrigues). Opposite vectors turn by π
// about `fallbackAxis`.
glm::dmat3 rotationBetween(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& fallbackAxis) {
    const glm::dvec3 v = glm::cross(a, b);
    const double c = glm::dot(a, b);
    if (c < -1.0 + 1e-12) {
        const glm::dvec3 k = fallbackAxis;
        return glm::dmat3(2.0 * glm::outerProduct(k, k)) - glm::dmat3(1.0);
    }
    // Column-major skew matrix of v: K x = v × x.
    const glm::dmat3 k(0.0, v.z, -v.y, -v.z, 0.0, v.x, v.y, -v.x, 0.0);
    return glm::dmat3(1.0) + k + (k * k) * (1.0 / (1.0 + c));
}

// Maps points of the +Y-axis layout to the requested axis and pivot: undo the +X → +Y turn, then turn
// +X onto the axis (the creator nodes' default axis is +X).
struct Frame {
    glm::dmat3 rotation{1.0};
    glm::dvec3 pivot{0.0};
    glm::dvec3 apply(const glm::dvec3& p) const { return rotation * p + pivot; }
};

bool makeFrame(const glm::dvec3& axis, const glm::dvec3& pivot, Frame* frame, std::string* error) {
    const double len = glm::length(axis);
    if (!std::isfinite(len) || len <= 0.0) return fail(error, "axis must be a non-zero finite vector");
    if (!std::isfinite(pivot.x) || !std::isfinite(pivot.y) || !std::isfinite(pivot.z)) {
        return fail(error, "pivot is not finite");
    }
    const glm::dvec3 a = axis / len;
    const glm::dmat3 yToX(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);  // (x, y, z) → (y, −x, z)
    frame->rotation = rotationBetween(glm::dvec3(1, 0, 0), a, glm::dvec3(0, 0, 1)) * yToX;
    frame->pivot = pivot;
    return true;
}

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

// Greville abscissae of a textbook knot vector: where CVs of a linearly parametrised line sit.
std::vector<double> greville(const std::vector<double>& knots, int degree, int cvCount) {
    std::vector<double> g(size_t(cvCount), 0.0);
    for (int i = 0; i < cvCount; ++i) {
        double s = 0.0;
        for (int k = 1; k <= degree; ++k) s += knots[size_t(i + k)];
        g[size_t(i)] = s / degree;
    }
    return g;
}

// Points (x, y) of a unit circle arc for a curve of `degree` (1 or 3) with `sections` spans; 1: the
// polygon through the points, 3: cubicArcCvs.
std::vector<glm::dvec2> arcCvs(int degree, double start, double sweep, int sections, bool periodic) {
    if (degree == 3) return cubicArcCvs(start, sweep, sections, periodic);
    std::vector<glm::dvec2> pts;
    const double step = sweep / sections;
    for (int k = 0; k <= sections; ++k) {
        const double a = start + step * k;
        pts.emplace_back(std::cos(a), std::sin(a));
    }
    if (periodic) pts.back() = pts.front();
    return pts;
}

struct Direction {
    int degree = 3;
    NurbsForm form = NurbsForm::Open;
    std::vector<double> knots;  // textbook
    int cvCount = 0;
};

Direction uniformDirection(int degree, int spans, double range, bool periodic) {
    Direction d;
    d.degree = degree;
    d.form = periodic ? NurbsForm::Periodic : NurbsForm::Open;
    d.knots = textbookKnotsFromMaya(uniformMayaKnots(degree, spans, range, periodic), degree, d.form);
    d.cvCount = spans + degree;
    return d;
}

// Tensor-product surface of revolution in the +Y layout: profile (radial, height) × unit cross-section
// (cos, sin) in the XZ plane, all weights 1.
std::optional<NurbsSurface> revolve(const Direction& du, const std::vector<glm::dvec2>& profile, const Direction& dv,
                                    const std::vector<glm::dvec2>& section, const Frame& frame, std::string* error) {
    std::vector<glm::dvec4> cvs;
    cvs.reserve(profile.size() * section.size());
    for (const glm::dvec2& pr : profile) {
        for (const glm::dvec2& c : section) {
            cvs.emplace_back(frame.apply(glm::dvec3(pr.x * c.x, pr.y, pr.x * c.y)), 1.0);
        }
    }
    return NurbsSurface::create(du.degree, dv.degree, du.form, dv.form, du.knots, dv.knots, du.cvCount, dv.cvCount,
                                std::move(cvs), false, error);
}

// Planar patch centred at `center` spanning ±uEdge/2 and ±vEdge/2 (normal along uEdge × vEdge),
// linearly parametrised over [0, patchesU] × [0, patchesV].
std::optional<NurbsSurface> planePatch(const glm::dvec3& center, const glm::dvec3& uEdge, const glm::dvec3& vEdge,
                                       int patchesU, int patchesV, int degree, const Frame& frame,
                                       std::string* error) {
    const Direction du = uniformDirection(degree, patchesU, patchesU, false);
    const Direction dv = uniformDirection(degree, patchesV, patchesV, false);
    const std::vector<double> gu = greville(du.knots, degree, du.cvCount);
    const std::vector<double> gv = greville(dv.knots, degree, dv.cvCount);
    std::vector<glm::dvec4> cvs;
    cvs.reserve(gu.size() * gv.size());
    for (double a : gu) {
        for (double b : gv) {
            const glm::dvec3 p = center + uEdge * (a / patchesU - 0.5) + vEdge * (b / patchesV - 0.5);
            cvs.emplace_back(frame.apply(p), 1.0);
        }
    }
    return NurbsSurface::create(degree, degree, NurbsForm::Open, NurbsForm::Open, du.knots, dv.knots, du.cvCount,
                                dv.cvCount, std::move(cvs), false, error);
}

bool checkRevolvedCommon(int degree, int sections, double startSweep, double endSweep, std::string* error) {
    if (degree != 1 && degree != 3) return fail(error, "degree " + std::to_string(degree) + " is not 1 or 3");
    if (!std::isfinite(startSweep) || !std::isfinite(endSweep)) return fail(error, "sweep angles are not finite");
    const double sweep = endSweep - startSweep;
    if (std::abs(sweep) < 1e-9) return fail(error, "sweep angle is zero");
    const bool full = isFullTurn(sweep);
    if (sections < 1 || (full && degree == 3 && sections < 3) || (full && sections < 3)) {
        return fail(error, "sections " + std::to_string(sections) + " are too few");
    }
    return true;
}

// The rational quadratic arc (The NURBS Book A7.1): 2n + 1 CVs (x, y, weight) for n arcs of at most 90°.
struct RationalArc {
    std::vector<glm::dvec3> cvs;  // (x, y) cartesian, z = weight
    std::vector<double> knots;    // textbook, clamped, double interior knots at 1 … n−1
};

RationalArc rationalArc(double start, double sweep, int minArcs) {
    const int n = std::max(minArcs, int(std::ceil(std::abs(sweep) / (0.5 * kPi) - 1e-9)));
    const double d = sweep / n;
    const double wm = std::cos(0.5 * d);
    RationalArc arc;
    arc.cvs.emplace_back(std::cos(start), std::sin(start), 1.0);
    for (int k = 0; k < n; ++k) {
        const double a0 = start + d * k;
        const double am = a0 + 0.5 * d;
        const double a1 = a0 + d;
        arc.cvs.emplace_back(std::cos(am) / wm, std::sin(am) / wm, wm);
        arc.cvs.emplace_back(std::cos(a1), std::sin(a1), 1.0);
    }
    if (isFullTurn(sweep)) arc.cvs.back() = glm::dvec3(arc.cvs.front().x, arc.cvs.front().y, 1.0);
    arc.knots = {0.0, 0.0, 0.0};
    for (int k = 1; k < n; ++k) {
        arc.knots.push_back(k);
        arc.knots.push_back(k);
    }
    arc.knots.insert(arc.knots.end(), {double(n), double(n), double(n)});
    return arc;
}

}  // namespace

std::vector<double> uniformMayaKnots(int degree, int spans, double range, bool periodic) {
    std::vector<double> k;
    const double h = range / spans;
    if (periodic) {
        for (int i = -(degree - 1); i <= spans + degree - 1; ++i) k.push_back(h * i);
        return k;
    }
    for (int i = 0; i < degree; ++i) k.push_back(0.0);
    for (int i = 1; i < spans; ++i) k.push_back(h * i);
    for (int i = 0; i < degree; ++i) k.push_back(range);
    return k;
}

std::vector<glm::dvec2> cubicArcCvs(double start, double sweep, int sections, bool periodic) {
    const double step = sweep / sections;
    auto at = [](double a) { return glm::dvec2(std::cos(a), std::sin(a)); };
    std::vector<glm::dvec2> cvs;
    if (periodic) {
        // Interpolation at the knots of a uniform periodic cubic: (P[k−1] + 4 P[k] + P[k+1]) / 6 = Q[k]
        // is solved by P[k] = Q[k] · 3 / (2 + cos Δ) (the system is circulant and Q a rotation orbit).
        const double scale = 3.0 / (2.0 + std::cos(step));
        for (int j = 0; j < sections + 3; ++j) cvs.push_back(scale * at(start + step * (((j - 1) % sections + sections) % sections)));
        return cvs;
    }
    // Open arc: clamped uniform cubic through Q[0..n] at knots 0..n with end derivatives along the
    // tangent, of length one span's chord. Unknowns P[2..n] form a tridiagonal system.
    const int n = sections;
    const double chord = 2.0 * std::sin(0.5 * std::abs(step));
    const double dir = step >= 0.0 ? 1.0 : -1.0;
    auto tangent = [&](double a) { return dir * glm::dvec2(-std::sin(a), std::cos(a)); };
    cvs.assign(size_t(n) + 3, glm::dvec2(0.0));
    cvs[0] = at(start);
    cvs[1] = at(start) + tangent(start) * (chord / 3.0);
    cvs[size_t(n) + 2] = at(start + sweep);
    cvs[size_t(n) + 1] = at(start + sweep) - tangent(start + sweep) * (chord / 3.0);
    if (n < 2) return cvs;
    const std::vector<double> knots = textbookKnotsFromMaya(uniformMayaKnots(3, n, n, false), 3, NurbsForm::Open);
    // Row k (k = 1..n−1): a P[k] + b P[k+1] + c P[k+2] = Q[k]; unknown x[m] = P[m+1], m = 1..n−1.
    const int m = n - 1;
    const size_t mCount = static_cast<size_t>(m);
    std::vector<double> a(mCount), b(mCount), c(mCount);
    std::vector<glm::dvec2> rhs(mCount);
    for (int k = 1; k <= n - 1; ++k) {
        double N[kMaxNurbsDegree + 1];
        const int span = findKnotSpan(3, knots, n + 3, double(k));
        basisFunctions(span, double(k), 3, knots, N);
        // span == k + 3: the non-zero functions at t = k belong to P[k], P[k+1], P[k+2].
        double coef[3] = {N[0], N[1], N[2]};
        glm::dvec2 r = at(start + step * k);
        const int row = k - 1;
        a[size_t(row)] = coef[0];
        b[size_t(row)] = coef[1];
        c[size_t(row)] = coef[2];
        if (k == 1) {
            r -= coef[0] * cvs[1];
            a[size_t(row)] = 0.0;
        }
        if (k == n - 1) {
            r -= coef[2] * cvs[size_t(n) + 1];
            c[size_t(row)] = 0.0;
        }
        rhs[size_t(row)] = r;
    }
    // Thomas algorithm.
    for (int i = 1; i < m; ++i) {
        const double w = a[size_t(i)] / b[size_t(i - 1)];
        b[size_t(i)] -= w * c[size_t(i - 1)];
        rhs[size_t(i)] -= w * rhs[size_t(i - 1)];
    }
    std::vector<glm::dvec2> x(mCount);
    x[size_t(m - 1)] = rhs[size_t(m - 1)] / b[size_t(m - 1)];
    for (int i = m - 2; i >= 0; --i) x[size_t(i)] = (rhs[size_t(i)] - c[size_t(i)] * x[size_t(i + 1)]) / b[size_t(i)];
    for (int i = 0; i < m; ++i) cvs[size_t(i) + 2] = x[size_t(i)];
    return cvs;
}

std::optional<NurbsSurface> makeNurbSphere(const NurbsSphereParams& p, std::string* error) {
    if (p.degree == 2) return makeRationalSphere(p, error);
    if (!finitePositive(p.radius)) return failWith(error, "radius must be > 0");
    if (!checkRevolvedCommon(p.degree, p.sections, p.startSweep, p.endSweep, error)) return std::nullopt;
    if (p.spans < 1 || (p.degree == 1 && p.spans < 2)) return failWith(error, "spans must be >= 1 (2 for degree 1)");
    Frame frame;
    if (!makeFrame(p.axis, p.pivot, &frame, error)) return std::nullopt;
    const double sweep = std::clamp(p.endSweep - p.startSweep, -kTwoPi, kTwoPi);
    const bool periodic = isFullTurn(sweep);

    std::vector<glm::dvec2> profile = arcCvs(p.degree, -0.5 * kPi, kPi, p.spans, false);
    for (glm::dvec2& q : profile) q *= p.radius;
    // The poles are exact points on the axis.
    profile.front() = glm::dvec2(0.0, -p.radius);
    profile.back() = glm::dvec2(0.0, p.radius);
    const std::vector<glm::dvec2> section = arcCvs(p.degree, p.startSweep, periodic ? kTwoPi : sweep, p.sections, periodic);
    const Direction du = uniformDirection(p.degree, p.spans, p.spans, false);
    const Direction dv = uniformDirection(p.degree, p.sections, p.sections, periodic);
    return revolve(du, profile, dv, section, frame, error);
}

std::optional<NurbsSurface> makeRationalSphere(const NurbsSphereParams& p, std::string* error) {
    if (!finitePositive(p.radius)) return failWith(error, "radius must be > 0");
    if (!std::isfinite(p.startSweep) || !std::isfinite(p.endSweep) || std::abs(p.endSweep - p.startSweep) < 1e-9) {
        return failWith(error, "sweep angles must be finite and differ");
    }
    Frame frame;
    if (!makeFrame(p.axis, p.pivot, &frame, error)) return std::nullopt;
    const double sweep = std::clamp(p.endSweep - p.startSweep, -kTwoPi, kTwoPi);
    const RationalArc profile = rationalArc(-0.5 * kPi, kPi, std::max(2, p.spans));
    const RationalArc section = rationalArc(p.startSweep, sweep, std::max(1, p.sections));
    std::vector<glm::dvec4> cvs;
    cvs.reserve(profile.cvs.size() * section.cvs.size());
    for (size_t i = 0; i < profile.cvs.size(); ++i) {
        glm::dvec3 pr = profile.cvs[i];
        if (i == 0) pr = glm::dvec3(0.0, -1.0, 1.0);
        if (i + 1 == profile.cvs.size()) pr = glm::dvec3(0.0, 1.0, 1.0);
        for (const glm::dvec3& c : section.cvs) {
            const double w = pr.z * c.z;
            const glm::dvec3 pos = frame.apply(p.radius * glm::dvec3(pr.x * c.x, pr.y, pr.x * c.y));
            cvs.emplace_back(pos * w, w);
        }
    }
    const NurbsForm formV = isFullTurn(sweep) ? NurbsForm::Closed : NurbsForm::Open;
    return NurbsSurface::create(2, 2, NurbsForm::Open, formV, profile.knots, section.knots, int(profile.cvs.size()),
                                int(section.cvs.size()), std::move(cvs), true, error);
}

std::optional<NurbsSurface> makeNurbPlane(const NurbsPlaneParams& p, std::string* error) {
    if (!finitePositive(p.width) || !finitePositive(p.lengthRatio)) {
        return failWith(error, "width and lengthRatio must be > 0");
    }
    if (p.patchesU < 1 || p.patchesV < 1) return failWith(error, "patchesU and patchesV must be >= 1");
    if (p.degree < 1 || p.degree > kMaxNurbsDegree) {
        return failWith(error, "degree " + std::to_string(p.degree) + " is unsupported");
    }
    Frame frame;
    if (!makeFrame(p.axis, p.pivot, &frame, error)) return std::nullopt;
    // In the +Y layout: width along X (U), length along −Z (V), so dP/du × dP/dv points along the axis.
    return planePatch(glm::dvec3(0.0), glm::dvec3(p.width, 0, 0), glm::dvec3(0, 0, -p.width * p.lengthRatio),
                      p.patchesU, p.patchesV, p.degree, frame, error);
}

namespace {

std::optional<NurbsSurface> lineRevolve(const NurbsCylinderParams& p, double topRadius, std::string* error) {
    if (!finitePositive(p.radius) || !finitePositive(p.heightRatio)) {
        return failWith(error, "radius and heightRatio must be > 0");
    }
    if (!checkRevolvedCommon(p.degree, p.sections, p.startSweep, p.endSweep, error)) return std::nullopt;
    if (p.spans < 1) return failWith(error, "spans must be >= 1");
    Frame frame;
    if (!makeFrame(p.axis, p.pivot, &frame, error)) return std::nullopt;
    const double sweep = std::clamp(p.endSweep - p.startSweep, -kTwoPi, kTwoPi);
    const bool periodic = isFullTurn(sweep);
    const double height = p.radius * p.heightRatio;
    const glm::dvec2 base(p.radius, -0.5 * height);
    const glm::dvec2 top(topRadius, 0.5 * height);
    const double length = glm::length(top - base);
    const Direction du = uniformDirection(p.degree, p.spans, length, false);
    std::vector<glm::dvec2> profile;
    for (double g : greville(du.knots, du.degree, du.cvCount)) profile.push_back(base + (top - base) * (g / length));
    const std::vector<glm::dvec2> section = arcCvs(p.degree, p.startSweep, periodic ? kTwoPi : sweep, p.sections, periodic);
    const Direction dv = uniformDirection(p.degree, p.sections, p.sections, periodic);
    return revolve(du, profile, dv, section, frame, error);
}

}  // namespace

std::optional<NurbsSurface> makeNurbCylinder(const NurbsCylinderParams& p, std::string* error) {
    return lineRevolve(p, p.radius, error);
}

std::optional<NurbsSurface> makeNurbCone(const NurbsConeParams& p, std::string* error) {
    return lineRevolve(p, 0.0, error);
}

std::optional<NurbsSurface> makeNurbTorus(const NurbsTorusParams& p, std::string* error) {
    if (!finitePositive(p.radius) || !finitePositive(p.heightRatio)) {
        return failWith(error, "radius and heightRatio must be > 0");
    }
    if (!checkRevolvedCommon(p.degree, p.sections, p.startSweep, p.endSweep, error)) return std::nullopt;
    if (!std::isfinite(p.minorSweep) || std::abs(p.minorSweep) < 1e-9) {
        return failWith(error, "minorSweep must be finite and non-zero");
    }
    const double minorSweep = std::clamp(p.minorSweep, -kTwoPi, kTwoPi);
    const bool minorPeriodic = isFullTurn(minorSweep);
    if (p.spans < 1 || (minorPeriodic && p.spans < 3)) {
        return failWith(error, "spans " + std::to_string(p.spans) + " are too few");
    }
    Frame frame;
    if (!makeFrame(p.axis, p.pivot, &frame, error)) return std::nullopt;
    const double sweep = std::clamp(p.endSweep - p.startSweep, -kTwoPi, kTwoPi);
    const bool periodic = isFullTurn(sweep);
    const double minor = p.radius * p.heightRatio;
    // Minor circle starts at the outer equator and turns towards +axis.
    std::vector<glm::dvec2> profile =
        arcCvs(p.degree, 0.0, minorPeriodic ? kTwoPi : minorSweep, p.spans, minorPeriodic);
    for (glm::dvec2& q : profile) q = glm::dvec2(p.radius, 0.0) + minor * q;
    const std::vector<glm::dvec2> section = arcCvs(p.degree, p.startSweep, periodic ? kTwoPi : sweep, p.sections, periodic);
    const Direction du = uniformDirection(p.degree, p.spans, p.spans, minorPeriodic);
    const Direction dv = uniformDirection(p.degree, p.sections, p.sections, periodic);
    return revolve(du, profile, dv, section, frame, error);
}

std::optional<std::vector<NurbsSurface>> makeNurbCube(const NurbsCubeParams& p, std::string* error) {
    if (!finitePositive(p.width) || !finitePositive(p.lengthRatio) || !finitePositive(p.heightRatio)) {
        return failWith(error, "width, lengthRatio and heightRatio must be > 0");
    }
    if (p.patchesU < 1 || p.patchesV < 1) return failWith(error, "patchesU and patchesV must be >= 1");
    if (p.degree < 1 || p.degree > kMaxNurbsDegree) {
        return failWith(error, "degree " + std::to_string(p.degree) + " is unsupported");
    }
    Frame frame;
    if (!makeFrame(p.axis, p.pivot, &frame, error)) return std::nullopt;
    const double w = p.width, h = p.width * p.heightRatio, l = p.width * p.lengthRatio;
    const glm::dvec3 X(w, 0, 0), Y(0, h, 0), Z(0, 0, l);
    struct Face {
        glm::dvec3 center, uEdge, vEdge;
    };
    // u × v points outwards on every face.
    const Face faces[6] = {
        {{0, 0.5 * h, 0}, X, -Z},   // top
        {{0, -0.5 * h, 0}, X, Z},   // bottom
        {{-0.5 * w, 0, 0}, Z, Y},   // left
        {{0.5 * w, 0, 0}, -Z, Y},   // right
        {{0, 0, 0.5 * l}, X, Y},    // front
        {{0, 0, -0.5 * l}, -X, Y},  // back
    };
    std::vector<NurbsSurface> out;
    for (const Face& f : faces) {
        auto s = planePatch(f.center, f.uEdge, f.vEdge, p.patchesU, p.patchesV, p.degree, frame, error);
        if (!s) return std::nullopt;
        out.push_back(std::move(*s));
    }
    return out;
}

std::optional<NurbsCurve> makeNurbCircle(const NurbsCircleParams& p, std::string* error) {
    if (!finitePositive(p.radius)) return failWith(error, "radius must be > 0");
    if (!checkRevolvedCommon(p.degree, p.sections, 0.0, p.sweep, error)) return std::nullopt;
    const double nlen = glm::length(p.normal);
    if (!std::isfinite(nlen) || nlen <= 0.0) return failWith(error, "normal must be a non-zero finite vector");
    if (!std::isfinite(p.center.x) || !std::isfinite(p.center.y) || !std::isfinite(p.center.z)) {
        return failWith(error, "center is not finite");
    }
    // Built in the XY plane (normal +Z) starting at +Y, then turned onto the normal; this matches the
    // CVs Maya writes for 8-section circles with normals +X and +Y.
    const glm::dmat3 rot = rotationBetween(glm::dvec3(0, 0, 1), p.normal / nlen, glm::dvec3(1, 0, 0));
    const double sweep = std::clamp(p.sweep, -kTwoPi, kTwoPi);
    const bool periodic = isFullTurn(sweep);
    const std::vector<glm::dvec2> pts = arcCvs(p.degree, 0.5 * kPi, periodic ? kTwoPi : sweep, p.sections, periodic);
    std::vector<glm::dvec4> cvs;
    for (const glm::dvec2& q : pts) cvs.emplace_back(rot * (p.radius * glm::dvec3(q, 0.0)) + p.center, 1.0);
    const Direction d = uniformDirection(p.degree, p.sections, p.sections, periodic);
    return NurbsCurve::create(p.degree, d.form, d.knots, std::move(cvs), false, error);
}

}  // namespace pushpin::geom
