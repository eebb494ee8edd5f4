// core/geom/nurbs_ops.cpp: revolve, loft and NURBS-to-polygons. See nurbs_ops.h for the constructions
// and what is verified against Maya.
#include "core/geom/nurbs_ops.h"

#include "core/geom/finite.h"
#include "core/geom/nurbs_primitives.h"
#include "core/geom/union_find.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::geom {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxSections = 1024;      // revolve sections (explicit or from the tolerance)
constexpr size_t kMaxLoftCurves = 512;  // the loft interpolation is a dense solve of N + 2 unknowns
constexpr size_t kMaxGridPoints = size_t(1) << 22;
constexpr int kMaxRefinePasses = 10;  // Maya's documented recursion depth for General

std::nullopt_t failWith(std::string* error, const std::string& msg) {
    if (error) *error = msg;
    return std::nullopt;
}

bool isFullTurn(double sweep) { return std::abs(std::abs(sweep) - kTwoPi) < 1e-9 || std::abs(sweep) > kTwoPi; }

bool anyRational(const std::vector<glm::dvec4>& cvs) {
    return std::any_of(cvs.begin(), cvs.end(), [](const glm::dvec4& c) { return c.w != 1.0; });
}

// ---- curves as plain arrays, so that edits can chain without revalidating at every step

struct Spline {
    int degree = 1;
    NurbsForm form = NurbsForm::Open;
    std::vector<double> knots;  // textbook
    std::vector<glm::dvec4> cvs;  // homogeneous
    int n() const { return int(cvs.size()); }
    double tMin() const { return knots[size_t(degree)]; }
    double tMax() const { return knots[cvs.size()]; }
};

Spline toSpline(const NurbsCurve& c) { return {c.degree(), c.form(), c.knots(), c.cvs()}; }

std::optional<NurbsCurve> toCurve(Spline s, std::string* error) {
    const bool rational = anyRational(s.cvs);
    return NurbsCurve::create(s.degree, s.form, std::move(s.knots), std::move(s.cvs), rational, error);
}

// Knots closer than this are one knot (relative to the magnitude of the vector's values).
double knotTolerance(const std::vector<double>& k) {
    double scale = 1.0;
    for (double x : k) scale = std::max(scale, std::abs(x));
    return 1e-10 * scale;
}

glm::dvec4 evalHomogeneous(const Spline& s, double t) {
    double N[kMaxNurbsDegree + 1];
    const int span = findKnotSpan(s.degree, s.knots, s.n(), t);
    basisFunctions(span, t, s.degree, s.knots, N);
    glm::dvec4 h(0.0);
    for (int k = 0; k <= s.degree; ++k) h += N[k] * s.cvs[size_t(span - s.degree + k)];
    return h;
}

glm::dvec3 evalPoint(const Spline& s, double t) {
    const glm::dvec4 h = evalHomogeneous(s, t);
    return glm::dvec3(h) / h.w;
}

// Boehm's single knot insertion (The NURBS Book A5.1, written for any t in the span's closed range).
void insertKnotInPlace(Spline& s, double t) {
    const int p = s.degree, n = s.n();
    const int k = findKnotSpan(p, s.knots, n, t);
    const std::vector<double>& u = s.knots;
    std::vector<glm::dvec4> q(size_t(n) + 1);
    for (int i = 0; i <= k - p; ++i) q[size_t(i)] = s.cvs[size_t(i)];
    for (int i = k - p + 1; i <= k; ++i) {
        const double denom = u[size_t(i + p)] - u[size_t(i)];
        const double a = denom > 0.0 ? (t - u[size_t(i)]) / denom : 0.0;
        q[size_t(i)] = a * s.cvs[size_t(i)] + (1.0 - a) * s.cvs[size_t(i - 1)];
    }
    for (int i = k + 1; i <= n; ++i) q[size_t(i)] = s.cvs[size_t(i - 1)];
    s.cvs = std::move(q);
    s.knots.insert(s.knots.begin() + k + 1, t);
}

int multiplicity(const std::vector<double>& knots, double t) {
    return int(std::count(knots.begin(), knots.end(), t));
}

// Values within the tolerance of `t` become exactly `t`, so multiplicities can be counted exactly.
void snapKnots(std::vector<double>& knots, double t, double tol) {
    for (double& k : knots)
        if (std::abs(k - t) <= tol) k = t;
}

bool endsMeet(const Spline& s) {
    const glm::dvec3 a = evalPoint(s, s.tMin()), b = evalPoint(s, s.tMax());
    double scale = 0.0;
    for (const glm::dvec4& c : s.cvs) scale = std::max(scale, glm::length(glm::dvec3(c) / c.w));
    return glm::length(a - b) <= 1e-9 * std::max(scale, 1e-30);
}

Spline clampSpline(Spline s) {
    const int p = s.degree;
    const double a = s.tMin(), b = s.tMax();
    const double tol = knotTolerance(s.knots);
    snapKnots(s.knots, a, tol);
    snapKnots(s.knots, b, tol);
    // After the insertions the curve passes through one CV at each domain end: with l the last index
    // of knot a, C(a) = P[l − p]; with e the first index of knot b, C(b) = P[e − 1].
    while (multiplicity(s.knots, a) < p) insertKnotInPlace(s, a);
    while (multiplicity(s.knots, b) < p) insertKnotInPlace(s, b);
    int l = 0;
    for (int i = 0; i < int(s.knots.size()); ++i)
        if (s.knots[size_t(i)] == a) l = i;
    int e = int(s.knots.size()) - 1;
    for (int i = int(s.knots.size()) - 1; i >= 0; --i)
        if (s.knots[size_t(i)] == b) e = i;
    Spline out;
    out.degree = p;
    out.cvs.assign(s.cvs.begin() + (l - p), s.cvs.begin() + e);
    out.knots.push_back(a);
    out.knots.insert(out.knots.end(), s.knots.begin() + (l - p + 1), s.knots.begin() + (e + p));
    out.knots.push_back(b);
    out.form = endsMeet(out) ? NurbsForm::Closed : NurbsForm::Open;
    return out;
}

// Distinct knot values strictly inside the domain, ascending.
std::vector<double> interiorKnots(const Spline& s) {
    std::vector<double> v;
    for (size_t i = size_t(s.degree) + 1; i < s.cvs.size(); ++i) {
        const double k = s.knots[i];
        if (k > s.tMin() && k < s.tMax() && (v.empty() || v.back() != k)) v.push_back(k);
    }
    return v;
}

// Exact degree elevation of a clamped spline: split into Bézier segments (every interior knot to
// multiplicity p), raise each segment one degree at a time (The NURBS Book eq. 5.36), keep the
// segments joined with interior knots of multiplicity q.
Spline elevateSpline(Spline s, int q) {
    const int p = s.degree;
    if (q <= p) return s;
    const std::vector<double> interior = interiorKnots(s);
    for (double t : interior)
        while (multiplicity(s.knots, t) < p) insertKnotInPlace(s, t);
    const int segments = int(interior.size()) + 1;
    Spline out;
    out.degree = q;
    out.form = s.form;
    for (int seg = 0; seg < segments; ++seg) {
        std::vector<glm::dvec4> b(s.cvs.begin() + seg * p, s.cvs.begin() + seg * p + p + 1);
        for (int d = p; d < q; ++d) {
            std::vector<glm::dvec4> r(size_t(d) + 2);
            r[0] = b[0];
            r[size_t(d) + 1] = b[size_t(d)];
            for (int i = 1; i <= d; ++i) {
                const double a = double(i) / double(d + 1);
                r[size_t(i)] = a * b[size_t(i - 1)] + (1.0 - a) * b[size_t(i)];
            }
            b = std::move(r);
        }
        out.cvs.insert(out.cvs.end(), b.begin() + (seg == 0 ? 0 : 1), b.end());
    }
    out.knots.assign(size_t(q) + 1, s.tMin());
    for (double t : interior) out.knots.insert(out.knots.end(), size_t(q), t);
    out.knots.insert(out.knots.end(), size_t(q) + 1, s.tMax());
    return out;
}

Spline reverseSpline(Spline s) {
    const double a = s.tMin(), b = s.tMax();
    std::vector<double> k(s.knots.size());
    for (size_t i = 0; i < k.size(); ++i) k[i] = a + b - s.knots[k.size() - 1 - i];
    s.knots = std::move(k);
    std::reverse(s.cvs.begin(), s.cvs.end());
    return s;
}

// Linear reparametrisation of the knots onto [a, b].
void reparametrise(Spline& s, double a, double b) {
    const double a0 = s.tMin(), b0 = s.tMax();
    if (a0 == a && b0 == b) return;
    const double scale = (b - a) / (b0 - a0);
    for (double& k : s.knots) k = a + (k - a0) * scale;
    s.knots[size_t(s.degree)] = a;
    s.knots[s.cvs.size()] = b;
}

// ---- dense linear solve (small systems: loft sections)

// Solves A X = B in place (A row-major n × n, B n rows of dvec4) by Gaussian elimination with partial
// pivoting. False when A is singular to working precision.
bool solveDense(std::vector<double>& A, std::vector<glm::dvec4>& B, size_t cols, size_t n) {
    // B holds n × cols right-hand sides, row-major.
    double maxAbs = 0.0;
    for (double x : A) maxAbs = std::max(maxAbs, std::abs(x));
    if (!(maxAbs > 0.0)) return false;
    for (size_t c = 0; c < n; ++c) {
        size_t piv = c;
        for (size_t r = c + 1; r < n; ++r)
            if (std::abs(A[r * n + c]) > std::abs(A[piv * n + c])) piv = r;
        if (!(std::abs(A[piv * n + c]) > 1e-13 * maxAbs)) return false;
        if (piv != c) {
            for (size_t k = 0; k < n; ++k) std::swap(A[c * n + k], A[piv * n + k]);
            for (size_t k = 0; k < cols; ++k) std::swap(B[c * cols + k], B[piv * cols + k]);
        }
        for (size_t r = c + 1; r < n; ++r) {
            const double f = A[r * n + c] / A[c * n + c];
            if (f == 0.0) continue;
            for (size_t k = c; k < n; ++k) A[r * n + k] -= f * A[c * n + k];
            for (size_t k = 0; k < cols; ++k) B[r * cols + k] -= f * B[c * cols + k];
        }
    }
    for (size_t c = n; c-- > 0;) {
        for (size_t k = 0; k < cols; ++k) {
            glm::dvec4 v = B[c * cols + k];
            for (size_t j = c + 1; j < n; ++j) v -= A[c * n + j] * B[j * cols + k];
            B[c * cols + k] = v / A[c * n + c];
        }
    }
    return true;
}

// Does curve `cur` run against `prev`? Open curves: the pairing of end points that is closer wins.
// Closed curves: their turning directions (Newell normals of sampled points) are compared.
bool runsAgainst(const Spline& cur, const Spline& prev) {
    const bool closedCur = endsMeet(cur), closedPrev = endsMeet(prev);
    if (closedCur && closedPrev) {
        auto turning = [](const Spline& s) {
            constexpr int kSamples = 32;
            glm::dvec3 nrm(0.0);
            glm::dvec3 last = evalPoint(s, s.tMin());
            for (int i = 1; i <= kSamples; ++i) {
                const glm::dvec3 p = evalPoint(s, s.tMin() + (s.tMax() - s.tMin()) * i / kSamples);
                nrm += glm::cross(last, p);
                last = p;
            }
            return nrm;
        };
        return glm::dot(turning(cur), turning(prev)) < 0.0;
    }
    const glm::dvec3 s0 = evalPoint(cur, cur.tMin()), e0 = evalPoint(cur, cur.tMax());
    const glm::dvec3 s1 = evalPoint(prev, prev.tMin()), e1 = evalPoint(prev, prev.tMax());
    return glm::length(s0 - e1) + glm::length(e0 - s1) < glm::length(s0 - s1) + glm::length(e0 - e1);
}

// Sections made compatible: one degree, one knot vector, one domain.
struct Sections {
    std::vector<Spline> curves;
    int degree = 1;
    NurbsForm form = NurbsForm::Open;
    std::vector<double> knots;
};

Sections compatibleSections(std::vector<Spline> in) {
    const double a = in[0].tMin(), b = in[0].tMax();
    for (Spline& s : in) reparametrise(s, a, b);
    bool same = true;
    const double tol = knotTolerance(in[0].knots);
    for (const Spline& s : in) {
        same = same && s.degree == in[0].degree && s.form == in[0].form && s.knots.size() == in[0].knots.size();
        for (size_t i = 0; same && i < s.knots.size(); ++i) same = std::abs(s.knots[i] - in[0].knots[i]) <= tol;
    }
    Sections out;
    if (same) {
        for (Spline& s : in) s.knots = in[0].knots;
        out.degree = in[0].degree;
        out.form = in[0].form;
        out.knots = in[0].knots;
        out.curves = std::move(in);
        return out;
    }
    int q = 1;
    for (const Spline& s : in) q = std::max(q, s.degree);
    bool allClosed = true;
    for (Spline& s : in) {
        s = elevateSpline(clampSpline(std::move(s)), q);
        allClosed = allClosed && s.form == NurbsForm::Closed;
    }
    // Union of the interior knots, each with its largest multiplicity; values within the tolerance
    // are one knot.
    std::vector<std::pair<double, int>> merged;
    for (Spline& s : in) {
        for (double t : interiorKnots(s)) {
            auto it = std::find_if(merged.begin(), merged.end(),
                                   [&](const auto& m) { return std::abs(m.first - t) <= tol; });
            if (it != merged.end()) {
                snapKnots(s.knots, it->first, tol);
                it->second = std::max(it->second, multiplicity(s.knots, it->first));
            } else {
                merged.emplace_back(t, multiplicity(s.knots, t));
            }
        }
    }
    for (Spline& s : in) {
        for (const auto& [t, mult] : merged) {
            snapKnots(s.knots, t, tol);
            while (multiplicity(s.knots, t) < mult) insertKnotInPlace(s, t);
        }
    }
    out.degree = q;
    out.form = allClosed ? NurbsForm::Closed : NurbsForm::Open;
    out.knots = in[0].knots;
    for (Spline& s : in) s.knots = out.knots;
    out.curves = std::move(in);
    return out;
}

// The loft direction: knots and CV rows (one row of section CVs per U CV) interpolating the sections
// at parameters t (t.size() = N, or N + 1 for a closed loft whose last entry closes the loop).
struct LoftDirection {
    int degree = 1;
    NurbsForm form = NurbsForm::Open;
    std::vector<double> knots;
    std::vector<std::vector<glm::dvec4>> rows;
};

std::optional<LoftDirection> interpolateSections(const Sections& sec, const std::vector<double>& t, int degree,
                                                 bool close, std::string* error) {
    const size_t N = sec.curves.size();
    const size_t K = sec.curves[0].cvs.size();
    LoftDirection d;
    d.degree = degree;
    if (degree == 1) {
        for (const Spline& s : sec.curves) d.rows.push_back(s.cvs);
        if (close) {
            d.rows.push_back(sec.curves[0].cvs);
            d.form = NurbsForm::Periodic;
            d.knots.push_back(t[0] - (t[N] - t[N - 1]));
            d.knots.insert(d.knots.end(), t.begin(), t.end());
            d.knots.push_back(t[N] + (t[1] - t[0]));
        } else {
            d.knots.push_back(t[0]);
            d.knots.insert(d.knots.end(), t.begin(), t.end());
            d.knots.push_back(t[N - 1]);
        }
        return d;
    }
    // Cubic. Open: clamped, interior knots at the inner sections, natural end conditions (zero second
    // derivative at the first and last section): N + 2 unknowns. Closed: periodic, N unknowns.
    const size_t M = close ? N : N + 2;
    const int cvCount = close ? int(N) + 3 : int(M);
    if (close) {
        const double T = t[N] - t[0];
        d.knots.assign(N + 7, 0.0);
        for (size_t k = 0; k <= N; ++k) d.knots[k + 3] = t[k];
        for (size_t k = 1; k <= 3; ++k) d.knots[N + 3 + k] = d.knots[3 + k] + T;
        for (size_t k = 1; k <= 3; ++k) d.knots[3 - k] = d.knots[3 + N - k] - T;
        d.form = NurbsForm::Periodic;
    } else {
        d.knots.assign(4, t[0]);
        for (size_t k = 1; k + 1 < N; ++k) d.knots.push_back(t[k]);
        d.knots.insert(d.knots.end(), 4, t[N - 1]);
    }
    std::vector<double> A(M * M, 0.0);
    std::vector<glm::dvec4> B(M * K, glm::dvec4(0.0));
    for (size_t k = 0; k < N; ++k) {
        double Nb[kMaxNurbsDegree + 1];
        const int span = findKnotSpan(3, d.knots, cvCount, t[k]);
        basisFunctions(span, t[k], 3, d.knots, Nb);
        for (int c = 0; c <= 3; ++c) A[k * M + size_t(span - 3 + c) % M] += Nb[c];
        for (size_t j = 0; j < K; ++j) B[k * K + j] = sec.curves[k].cvs[j];
    }
    if (!close) {
        const std::vector<double>& u = d.knots;
        const size_t n = M;
        const double d1a = u[4] - u[1], d2a = u[5] - u[2];
        const double d1b = u[n + 1] - u[n - 2], d2b = u[n + 2] - u[n - 1];
        if (!(d1a > 0 && d2a > 0 && d1b > 0 && d2b > 0)) return failWith(error, "loft section parameters coincide");
        double* rowA = &A[N * M];
        rowA[0] = 1.0 / d1a;
        rowA[1] = -(1.0 / d1a + 1.0 / d2a);
        rowA[2] = 1.0 / d2a;
        double* rowB = &A[(N + 1) * M];
        rowB[n - 3] += 1.0 / d1b;
        rowB[n - 2] += -(1.0 / d1b + 1.0 / d2b);
        rowB[n - 1] += 1.0 / d2b;
    }
    if (!solveDense(A, B, K, M)) return failWith(error, "the loft interpolation is singular");
    for (size_t i = 0; i < size_t(cvCount); ++i) {
        const size_t src = i % M;
        d.rows.emplace_back(B.begin() + std::ptrdiff_t(src * K), B.begin() + std::ptrdiff_t(src * K + K));
    }
    return d;
}

// Adds sectionSpans − 1 knots inside every span between sections (column by column; a periodic
// direction is clamped at its seam first).
void subdivideLoftDirection(LoftDirection& d, const std::vector<double>& t, int sectionSpans) {
    const size_t K = d.rows[0].size();
    std::vector<Spline> columns(K);
    for (size_t j = 0; j < K; ++j) {
        Spline& s = columns[j];
        s.degree = d.degree;
        s.form = d.form;
        s.knots = d.knots;
        for (const auto& row : d.rows) s.cvs.push_back(row[j]);
        if (s.form == NurbsForm::Periodic) s = clampSpline(std::move(s));
        for (size_t k = 0; k + 1 < t.size(); ++k)
            for (int m = 1; m < sectionSpans; ++m) insertKnotInPlace(s, t[k] + (t[k + 1] - t[k]) * m / sectionSpans);
    }
    d.form = d.form == NurbsForm::Periodic ? NurbsForm::Closed : d.form;
    d.knots = columns[0].knots;
    d.rows.assign(columns[0].cvs.size(), std::vector<glm::dvec4>(K));
    for (size_t j = 0; j < K; ++j)
        for (size_t i = 0; i < columns[j].cvs.size(); ++i) d.rows[i][j] = columns[j].cvs[i];
}

// ---- revolve helpers

// Unit-circle section points (x along the radial direction, y along radial × axis) and the V
// direction's knots (Maya form) for a sweep.
struct SweepSection {
    std::vector<glm::dvec2> points;
    std::vector<double> mayaKnots;
    NurbsForm form = NurbsForm::Open;
};

SweepSection sweepSection(int degree, double start, double sweep, int sections) {
    SweepSection s;
    const bool periodic = isFullTurn(sweep);
    s.form = periodic ? NurbsForm::Periodic : NurbsForm::Open;
    if (degree == 3) {
        s.points = cubicArcCvs(start, periodic ? kTwoPi : sweep, sections, periodic);
    } else {
        const double step = (periodic ? kTwoPi : sweep) / sections;
        for (int k = 0; k <= sections; ++k) s.points.emplace_back(std::cos(start + step * k), std::sin(start + step * k));
        if (periodic) s.points.back() = s.points.front();
    }
    s.mayaKnots = uniformMayaKnots(degree, sections, sections, periodic);
    return s;
}

// Largest |radius − 1| of the unit sweep, sampled 16 times per span.
double sweepRadialError(int degree, double sweep, int sections) {
    if (degree == 1) return 1.0 - std::cos(0.5 * std::abs((isFullTurn(sweep) ? kTwoPi : sweep) / sections));
    const SweepSection s = sweepSection(3, 0.0, sweep, sections);
    Spline c;
    c.degree = 3;
    c.form = s.form;
    c.knots = textbookKnotsFromMaya(s.mayaKnots, 3, s.form);
    for (const glm::dvec2& q : s.points) c.cvs.emplace_back(q.x, q.y, 0.0, 1.0);
    double worst = 0.0;
    const int samples = 16 * sections;
    for (int i = 0; i <= samples; ++i) {
        const glm::dvec3 p = evalPoint(c, c.tMin() + (c.tMax() - c.tMin()) * i / samples);
        worst = std::max(worst, std::abs(glm::length(p) - 1.0));
    }
    return worst;
}

struct RevolveFrame {
    glm::dvec3 axis{0.0};
    glm::dvec3 pivot{0.0};
};

std::optional<NurbsSurface> buildRevolve(const NurbsCurve& profile, const RevolveFrame& f, int degree,
                                         double start, double sweep, int sections, std::string* error) {
    const SweepSection sec = sweepSection(degree, start, sweep, sections);
    const size_t nv = sec.points.size();
    std::vector<glm::dvec4> cvs;
    cvs.reserve(size_t(profile.cvCount()) * nv);
    for (const glm::dvec4& c : profile.cvs()) {
        const glm::dvec3 x = glm::dvec3(c) / c.w;
        const glm::dvec3 d = x - f.pivot;
        const double h = glm::dot(d, f.axis);
        const glm::dvec3 r = d - h * f.axis;
        const glm::dvec3 e2 = glm::cross(r, f.axis);
        const glm::dvec3 onAxis = f.pivot + h * f.axis;
        for (const glm::dvec2& q : sec.points) cvs.emplace_back((onAxis + q.x * r + q.y * e2) * c.w, c.w);
    }
    return NurbsSurface::create(profile.degree(), degree, profile.form(), sec.form, profile.knots(),
                                textbookKnotsFromMaya(sec.mayaKnots, degree, sec.form), profile.cvCount(), int(nv),
                                std::move(cvs), profile.rational(), error);
}

// ---- tessellation helpers

// Distinct knot values over the domain: the span boundaries, first = min, last = max.
std::vector<double> spanBreaks(const std::vector<double>& knots, double lo, double hi) {
    std::vector<double> b{lo};
    for (double k : knots)
        if (k > b.back() && k < hi) b.push_back(k);
    b.push_back(hi);
    return b;
}

struct DirectionView {
    const NurbsSurface& s;
    bool isU;
    double lo() const { return isU ? s.uMin() : s.vMin(); }
    double hi() const { return isU ? s.uMax() : s.vMax(); }
    double otherLo() const { return isU ? s.vMin() : s.uMin(); }
    double otherHi() const { return isU ? s.vMax() : s.uMax(); }
    const std::vector<double>& knots() const { return isU ? s.knotsU() : s.knotsV(); }
    glm::dvec3 at(double t, double other) const { return isU ? s.point(t, other) : s.point(other, t); }
};

std::vector<double> equalSegments(double lo, double hi, int segments) {
    std::vector<double> t;
    for (int k = 0; k < segments; ++k) t.push_back(lo + (hi - lo) * k / segments);
    t.push_back(hi);
    return t;
}

// `segments` segments of equal 3D length along the isoparm through the middle of the other direction.
std::vector<double> equalLengthSegments(const DirectionView& d, int segments) {
    const int spans = int(spanBreaks(d.knots(), d.lo(), d.hi()).size()) - 1;
    const int samples = std::clamp(64 * spans, 64, 4096);
    const double mid = 0.5 * (d.otherLo() + d.otherHi());
    std::vector<double> len(size_t(samples) + 1, 0.0);
    glm::dvec3 last = d.at(d.lo(), mid);
    for (int i = 1; i <= samples; ++i) {
        const glm::dvec3 p = d.at(d.lo() + (d.hi() - d.lo()) * i / samples, mid);
        len[size_t(i)] = len[size_t(i) - 1] + glm::length(p - last);
        last = p;
    }
    const double total = len.back();
    if (!(total > 0.0) || !std::isfinite(total)) return equalSegments(d.lo(), d.hi(), segments);
    std::vector<double> t{d.lo()};
    size_t i = 1;
    for (int k = 1; k < segments; ++k) {
        const double target = total * k / segments;
        while (i < size_t(samples) && len[i] < target) ++i;
        const double f = (target - len[i - 1]) / std::max(len[i] - len[i - 1], 1e-300);
        t.push_back(d.lo() + (d.hi() - d.lo()) * (double(i - 1) + f) / samples);
    }
    t.push_back(d.hi());
    return t;
}

std::vector<double> perSpanSegments(const DirectionView& d, int perSpan) {
    const std::vector<double> b = spanBreaks(d.knots(), d.lo(), d.hi());
    std::vector<double> t;
    for (size_t s = 0; s + 1 < b.size(); ++s)
        for (int k = 0; k < perSpan; ++k) t.push_back(b[s] + (b[s + 1] - b[s]) * k / perSpan);
    t.push_back(b.back());
    return t;
}

struct Refinement {
    bool useChordHeight = false;
    double chordHeight = 0.0;
    bool useRatio = false;
    double ratio = 0.0;
    bool active() const { return useChordHeight || useRatio; }
};

// Halves the intervals of `ts` whose midpoint strays from the chord on any of (up to 64 of) the grid
// lines `others`; returns whether any interval was split.
bool refineOnce(const DirectionView& d, std::vector<double>& ts, const std::vector<double>& others,
                const Refinement& r) {
    const size_t step = std::max<size_t>(1, others.size() / 64);
    std::vector<double> out{ts[0]};
    bool split = false;
    for (size_t i = 0; i + 1 < ts.size(); ++i) {
        const double a = ts[i], b = ts[i + 1], m = 0.5 * (a + b);
        bool fails = false;
        for (size_t k = 0; k < others.size() && !fails; k += step) {
            const glm::dvec3 pa = d.at(a, others[k]), pb = d.at(b, others[k]), pm = d.at(m, others[k]);
            const double height = glm::length(pm - 0.5 * (pa + pb));
            const double chord = glm::length(pb - pa);
            if (r.useChordHeight && height > r.chordHeight) fails = true;
            if (r.useRatio && height > (1.0 - r.ratio) * chord) fails = true;
        }
        if (fails) {
            out.push_back(m);
            split = true;
        }
        out.push_back(b);
    }
    ts = std::move(out);
    return split;
}

// Grid points (u fastest) with one UV each, welded where they coincide along seams and poles.
Mesh gridMesh(const std::vector<glm::dvec3>& pts, const std::vector<glm::dvec2>& uvs, size_t m, size_t n,
              bool triangles) {
    Bounds3 box;
    for (const glm::dvec3& p : pts) box.extend(p);
    const glm::dvec3 size = box.size();
    const double tol = 1e-7 * std::max({size.x, size.y, size.z, 1e-30});
    auto idx = [m](size_t i, size_t j) { return j * m + i; };
    auto same = [&](size_t a, size_t b) { return glm::length(pts[a] - pts[b]) <= tol; };
    LowestRootSets welded(pts.size());
    auto weld = [&](size_t a, size_t b) { welded.join(uint32_t(a), uint32_t(b)); };
    bool seamU = m > 2, seamV = n > 2;
    for (size_t j = 0; j < n && seamU; ++j) seamU = same(idx(0, j), idx(m - 1, j));
    for (size_t i = 0; i < m && seamV; ++i) seamV = same(idx(i, 0), idx(i, n - 1));
    if (seamU)
        for (size_t j = 0; j < n; ++j) weld(idx(0, j), idx(m - 1, j));
    if (seamV)
        for (size_t i = 0; i < m; ++i) weld(idx(i, 0), idx(i, n - 1));
    for (size_t j = 0; j < n; ++j) {
        bool collapsed = true;
        for (size_t i = 1; i < m && collapsed; ++i) collapsed = same(idx(0, j), idx(i, j));
        if (collapsed)
            for (size_t i = 1; i < m; ++i) weld(idx(0, j), idx(i, j));
    }
    for (size_t i = 0; i < m; ++i) {
        bool collapsed = true;
        for (size_t j = 1; j < n && collapsed; ++j) collapsed = same(idx(i, 0), idx(i, j));
        if (collapsed)
            for (size_t j = 1; j < n; ++j) weld(idx(i, 0), idx(i, j));
    }

    Mesh mesh;
    std::vector<uint32_t> vertexOf(pts.size());
    for (size_t g = 0; g < pts.size(); ++g) {
        const uint32_t r = welded.find(uint32_t(g));
        if (r == g) {
            vertexOf[g] = uint32_t(mesh.points.size());
            mesh.points.push_back(glm::vec3(pts[g]));
        } else {
            vertexOf[g] = vertexOf[r];
        }
    }
    UvSet set;
    set.name = "map1";
    for (const glm::dvec2& uv : uvs) set.uvs.push_back(glm::vec2(uv));
    auto emit = [&](std::initializer_list<size_t> corners) {
        for (size_t g : corners) {
            mesh.faceVertices.push_back(vertexOf[g]);
            set.faceVertexUvs.push_back(int32_t(g));
        }
        mesh.loopStarts.push_back(uint32_t(mesh.faceVertices.size()));
        mesh.faceLoopStarts.push_back(uint32_t(mesh.loopStarts.size() - 1));
    };
    for (size_t j = 0; j + 1 < n; ++j) {
        for (size_t i = 0; i + 1 < m; ++i) {
            const size_t quad[4] = {idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)};
            size_t keep[4];
            size_t count = 0;
            for (size_t c = 0; c < 4; ++c) {
                const size_t g = quad[c];
                if (count > 0 && vertexOf[keep[count - 1]] == vertexOf[g]) continue;
                keep[count++] = g;
            }
            while (count > 1 && vertexOf[keep[count - 1]] == vertexOf[keep[0]]) --count;
            if (count < 3) continue;
            if (count == 3) {
                emit({keep[0], keep[1], keep[2]});
            } else if (triangles) {
                emit({keep[0], keep[1], keep[2]});
                emit({keep[0], keep[2], keep[3]});
            } else {
                emit({keep[0], keep[1], keep[2], keep[3]});
            }
        }
    }
    mesh.uvSets.push_back(std::move(set));
    return mesh;
}

void note(std::vector<std::string>* notes, std::string text) {
    if (notes) notes->push_back(std::move(text));
}

}  // namespace

// ---- public edits

std::optional<NurbsCurve> transformCurve(const NurbsCurve& c, const glm::dmat4& m, std::string* error) {
    std::vector<glm::dvec4> cvs;
    cvs.reserve(c.cvs().size());
    for (const glm::dvec4& p : c.cvs()) cvs.push_back(m * p);
    return NurbsCurve::create(c.degree(), c.form(), c.knots(), std::move(cvs), c.rational() || anyRational(cvs), error);
}

std::optional<NurbsSurface> transformSurface(const NurbsSurface& s, const glm::dmat4& m, std::string* error) {
    std::vector<glm::dvec4> cvs;
    cvs.reserve(s.cvs().size());
    for (const glm::dvec4& p : s.cvs()) cvs.push_back(m * p);
    const bool rational = s.rational() || anyRational(cvs);
    return NurbsSurface::create(s.degreeU(), s.degreeV(), s.formU(), s.formV(), s.knotsU(), s.knotsV(), s.cvCountU(),
                                s.cvCountV(), std::move(cvs), rational, error);
}

std::optional<NurbsCurve> reverseCurve(const NurbsCurve& c) { return toCurve(reverseSpline(toSpline(c)), nullptr); }

std::optional<NurbsCurve> insertKnot(const NurbsCurve& c, double t) {
    if (!(t >= c.tMin() && t <= c.tMax())) return std::nullopt;
    Spline s = toSpline(c);
    insertKnotInPlace(s, t);
    return toCurve(std::move(s), nullptr);
}

std::optional<NurbsCurve> clampCurve(const NurbsCurve& c) { return toCurve(clampSpline(toSpline(c)), nullptr); }

std::optional<NurbsCurve> elevateCurveDegree(const NurbsCurve& c, int degree) {
    if (degree < c.degree() || degree > kMaxNurbsDegree) return std::nullopt;
    return toCurve(elevateSpline(clampSpline(toSpline(c)), degree), nullptr);
}

// ---- surface edits along one direction

namespace {

// The lines of CVs of `s` along U (directionU) or V, each as a spline in that direction.
std::vector<Spline> surfaceLines(const NurbsSurface& s, bool directionU) {
    const int lines = directionU ? s.cvCountV() : s.cvCountU();
    const int along = directionU ? s.cvCountU() : s.cvCountV();
    std::vector<Spline> out;
    out.reserve(size_t(lines));
    for (int l = 0; l < lines; ++l) {
        Spline line{directionU ? s.degreeU() : s.degreeV(), directionU ? s.formU() : s.formV(),
                    directionU ? s.knotsU() : s.knotsV(), {}};
        line.cvs.reserve(size_t(along));
        for (int i = 0; i < along; ++i) line.cvs.push_back(directionU ? s.cv(i, l) : s.cv(l, i));
        out.push_back(std::move(line));
    }
    return out;
}

// The surface whose lines along U (directionU) or V are CVs [first, first + count) of `lines`
// (which share degree and knots), with `knots` and `form` in that direction and the other
// direction of `s`.
std::optional<NurbsSurface> surfaceFromLines(const NurbsSurface& s, bool directionU, const std::vector<Spline>& lines,
                                             size_t first, int count, std::vector<double> knots, NurbsForm form,
                                             std::string* error) {
    const size_t n = lines.size();
    std::vector<glm::dvec4> cvs(size_t(count) * n);
    for (size_t l = 0; l < n; ++l)
        for (int i = 0; i < count; ++i)
            cvs[directionU ? size_t(i) * n + l : l * size_t(count) + size_t(i)] = lines[l].cvs[first + size_t(i)];
    const int p = lines.front().degree;
    const bool rational = anyRational(cvs);
    return directionU ? NurbsSurface::create(p, s.degreeV(), form, s.formV(), std::move(knots), s.knotsV(), count, int(n),
                                             std::move(cvs), rational, error)
                      : NurbsSurface::create(s.degreeU(), p, s.formU(), form, s.knotsU(), std::move(knots), int(n), count,
                                             std::move(cvs), rational, error);
}

}  // namespace

std::optional<std::vector<NurbsSurface>> detachSurface(const NurbsSurface& s, bool directionU, std::vector<double> params,
                                                       std::string* error) {
    const NurbsForm form = directionU ? s.formU() : s.formV();
    if (form == NurbsForm::Periodic) return failWith(error, "detaching across a periodic direction is not evaluated");
    const int p = directionU ? s.degreeU() : s.degreeV();
    const int along = directionU ? s.cvCountU() : s.cvCountV();
    const std::vector<double>& knots = directionU ? s.knotsU() : s.knotsV();
    // The cuts strictly inside the domain, ascending, each once.
    const double tol = knotTolerance(knots);
    const double lo = knots[size_t(p)], hi = knots[size_t(along)];
    std::vector<double> cuts;
    for (double t : params) {
        if (!std::isfinite(t)) return failWith(error, "a detach parameter is not finite");
        if (t > lo + tol && t < hi - tol) cuts.push_back(t);
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end(), [&](double a, double b) { return b - a <= tol; }), cuts.end());
    if (cuts.size() > kMaxSurfaceEdits) return failWith(error, "more than " + std::to_string(kMaxSurfaceEdits) + " cuts");
    // Every line, clamped, with each cut raised to multiplicity p: the same steps on every line
    // give every line the same knots.
    std::vector<Spline> lines = surfaceLines(s, directionU);
    for (Spline& line : lines) {
        line = clampSpline(std::move(line));
        for (double t : cuts) {
            snapKnots(line.knots, t, tol);
            while (multiplicity(line.knots, t) < p) insertKnotInPlace(line, t);
        }
    }
    const std::vector<double>& k = lines.front().knots;
    std::vector<double> ends{k[size_t(p)]};
    ends.insert(ends.end(), cuts.begin(), cuts.end());
    ends.push_back(k[lines.front().cvs.size()]);
    std::vector<NurbsSurface> pieces;
    for (size_t r = 0; r + 1 < ends.size(); ++r) {
        const double a = ends[r], b = ends[r + 1];
        // The CV at a is P[ia − p] (ia the last index of knot a); the one at b is P[ib − 1].
        size_t ia = 0, ib = k.size();
        for (size_t i = 0; i < k.size(); ++i)
            if (k[i] == a) ia = i;
        for (size_t i = k.size(); i-- > 0;)
            if (k[i] == b) ib = i;
        if (ia < size_t(p) || ib <= ia) return failWith(error, "a detached piece has no span");
        std::vector<double> pieceKnots(size_t(p) + 1, a);
        pieceKnots.insert(pieceKnots.end(), k.begin() + std::ptrdiff_t(ia) + 1, k.begin() + std::ptrdiff_t(ib));
        pieceKnots.insert(pieceKnots.end(), size_t(p) + 1, b);
        std::optional<NurbsSurface> piece = surfaceFromLines(s, directionU, lines, ia - size_t(p), int(ib - ia) + p,
                                                             std::move(pieceKnots), NurbsForm::Open, error);
        if (!piece) return std::nullopt;
        pieces.push_back(std::move(*piece));
    }
    return pieces;
}

std::optional<NurbsSurface> insertSurfaceKnots(const NurbsSurface& s, bool directionU,
                                               const std::vector<std::pair<double, int>>& inserts, std::string* error) {
    const NurbsForm form = directionU ? s.formU() : s.formV();
    if (form == NurbsForm::Periodic) return failWith(error, "inserting knots across a periodic direction is not evaluated");
    const int p = directionU ? s.degreeU() : s.degreeV();
    std::vector<Spline> lines = surfaceLines(s, directionU);
    const double tol = knotTolerance(lines.front().knots);
    if (inserts.size() > kMaxSurfaceEdits) return failWith(error, "more than " + std::to_string(kMaxSurfaceEdits) + " knots to insert");
    for (const auto& [t, count] : inserts) {
        if (!std::isfinite(t)) return failWith(error, "a knot to insert is not finite");
        if (!(t >= lines.front().tMin() && t <= lines.front().tMax())) continue;  // outside: nothing to insert
        for (Spline& line : lines) {
            snapKnots(line.knots, t, tol);
            // Up to full multiplicity p; more would break the surface.
            for (int k = 0; k < count && multiplicity(line.knots, t) < p; ++k) insertKnotInPlace(line, t);
        }
    }
    std::vector<double> knots = lines.front().knots;
    const int count = lines.front().n();
    return surfaceFromLines(s, directionU, lines, 0, count, std::move(knots), form, error);
}

std::optional<NurbsSurface> rebuildSurface(const NurbsSurface& s, const RebuildParams& params, std::string* error) {
    if (params.spansU < 1 || params.spansV < 1 || params.spansU > kMaxRebuildSpans || params.spansV > kMaxRebuildSpans)
        return failWith(error, "spans must be 1 to " + std::to_string(kMaxRebuildSpans));
    if (params.degreeU < 1 || params.degreeV < 1 || params.degreeU > kMaxNurbsDegree || params.degreeV > kMaxNurbsDegree)
        return failWith(error, "degrees must be 1 to " + std::to_string(kMaxNurbsDegree));
    std::optional<NurbsSurface> out = s;
    for (const bool directionU : {true, false}) {
        if (!(directionU ? params.rebuildU : params.rebuildV)) continue;
        const NurbsSurface& in = *out;
        const NurbsForm form = directionU ? in.formU() : in.formV();
        const double a = directionU ? in.uMin() : in.vMin(), b = directionU ? in.uMax() : in.vMax();
        const int spans = directionU ? params.spansU : params.spansV;
        double lo = a, hi = b;
        if (params.range == RebuildRange::ZeroToOne) lo = 0.0, hi = 1.0;
        if (params.range == RebuildRange::ZeroToSpans) lo = 0.0, hi = double(params.keepControlPoints ? (directionU ? in.spansU() : in.spansV()) : spans);
        std::vector<Spline> lines = surfaceLines(in, directionU);
        if (params.keepControlPoints) {
            // The same CVs over the new range.
            std::vector<double> knots = lines.front().knots;
            for (double& k : knots) k = lo + (k - a) / (b - a) * (hi - lo);
            const int count = lines.front().n();
            out = surfaceFromLines(in, directionU, lines, 0, count, std::move(knots), form, error);
            if (!out) return std::nullopt;
            continue;
        }
        const int q = directionU ? params.degreeU : params.degreeV;
        const bool periodic = form == NurbsForm::Periodic;
        // Uniform knots over [lo, hi]: clamped ends, or the periodic pattern (q spans past each end).
        std::vector<double> knots;
        const double step = (hi - lo) / spans;
        if (periodic) {
            for (int i = -q; i <= spans + q; ++i) knots.push_back(lo + step * i);
        } else {
            knots.assign(size_t(q) + 1, lo);
            for (int i = 1; i < spans; ++i) knots.push_back(lo + step * i);
            knots.insert(knots.end(), size_t(q) + 1, hi);
        }
        const int count = spans + q;                   // CVs along the direction
        const int unknowns = periodic ? spans : count;  // a periodic line repeats its first q CVs
        // Interpolate each line at the Greville abscissae of the new knots (wrapped into the domain).
        std::vector<double> sites(static_cast<size_t>(unknowns));
        for (int i = 0; i < unknowns; ++i) {
            double g = 0.0;
            for (int k = 1; k <= q; ++k) g += knots[size_t(i + k)];
            g /= q;
            if (periodic) g = lo + std::fmod(std::fmod(g - lo, hi - lo) + (hi - lo), hi - lo);
            sites[size_t(i)] = std::clamp(g, lo, hi);
        }
        std::vector<double> matrix(size_t(unknowns) * size_t(unknowns), 0.0);
        double basis[kMaxNurbsDegree + 1];
        for (int r = 0; r < unknowns; ++r) {
            const int span = findKnotSpan(q, knots, count, sites[size_t(r)]);
            basisFunctions(span, sites[size_t(r)], q, knots, basis);
            for (int k = 0; k <= q; ++k) {
                const int cv = span - q + k;
                matrix[size_t(r) * size_t(unknowns) + size_t(periodic ? cv % spans : cv)] += basis[k];
            }
        }
        // Every line's samples as the columns of one system.
        const size_t columns = lines.size();
        std::vector<glm::dvec4> rhs(size_t(unknowns) * columns);
        for (size_t l = 0; l < columns; ++l)
            for (int r = 0; r < unknowns; ++r)
                rhs[size_t(r) * columns + l] = evalHomogeneous(lines[l], a + (sites[size_t(r)] - lo) / (hi - lo) * (b - a));
        if (!solveDense(matrix, rhs, columns, size_t(unknowns))) return failWith(error, "the rebuilt surface cannot fit the input");
        for (size_t l = 0; l < columns; ++l) {
            std::vector<glm::dvec4> cvs;
            cvs.reserve(size_t(count));
            for (int r = 0; r < unknowns; ++r) cvs.push_back(rhs[size_t(r) * columns + l]);
            for (int k = 0; periodic && k < q; ++k) cvs.push_back(cvs[size_t(k)]);
            lines[l] = Spline{q, form, knots, std::move(cvs)};
        }
        out = surfaceFromLines(in, directionU, lines, 0, count, knots, form, error);
        if (!out) return std::nullopt;
    }
    return out;
}

// ---- extrude

std::optional<NurbsSurface> extrudeCurve(const NurbsCurve& profile, const NurbsCurve* path, const ExtrudeParams& p,
                                         std::string* error) {
    const std::vector<glm::dvec4>& pc = profile.cvs();
    auto cartesian = [](const glm::dvec4& c) { return glm::dvec3(c) / c.w; };
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec4& c : pc) {
        lo = glm::min(lo, cartesian(c));
        hi = glm::max(hi, cartesian(c));
    }
    const glm::dvec3 centre = 0.5 * (lo + hi);
    if (p.type == ExtrudeType::Distance) {
        const double len = glm::length(p.direction);
        if (!std::isfinite(len) || len <= 0.0 || !std::isfinite(p.length)) return failWith(error, "the direction or length is not usable");
        if (p.degreeAlongLength < 1 || p.degreeAlongLength > kMaxNurbsDegree) return failWith(error, "degreeAlongLength is out of range");
        const glm::dvec3 d = p.direction / len * p.length;
        const int rows = p.degreeAlongLength + 1;
        std::vector<glm::dvec4> cvs;
        for (int i = 0; i < rows; ++i)
            for (const glm::dvec4& c : pc) cvs.emplace_back((cartesian(c) + d * (double(i) / (rows - 1))) * c.w, c.w);
        std::vector<double> knots(size_t(rows), 0.0);
        knots.insert(knots.end(), size_t(rows), 1.0);
        return NurbsSurface::create(p.degreeAlongLength, profile.degree(), NurbsForm::Open, profile.form(), std::move(knots),
                                    profile.knots(), rows, profile.cvCount(), std::move(cvs), profile.rational(), error);
    }
    if (!path) return failWith(error, "a flat or tube extrusion needs a path curve");
    // The path runs from the end nearer the profile (unless the surface is placed on the path).
    std::optional<NurbsCurve> way = *path;
    if (!p.fixedPath && glm::length(path->point(path->tMax()) - centre) < glm::length(path->point(path->tMin()) - centre))
        way = reverseCurve(*path);
    if (!way) return failWith(error, "the path curve cannot be reversed");
    const glm::dvec3 start = way->point(way->tMin());
    const glm::dvec3 anchor = p.fixedPath ? centre : start;  // the profile point that rides on the path
    if (p.type == ExtrudeType::Flat) {
        // A translational surface: CV (i, j) = path CV i + profile CV j − anchor, weights multiplied.
        std::vector<glm::dvec4> cvs;
        for (const glm::dvec4& q : way->cvs())
            for (const glm::dvec4& c : pc) {
                const double w = q.w * c.w;
                cvs.emplace_back((cartesian(q) + cartesian(c) - anchor) * w, w);
            }
        return NurbsSurface::create(way->degree(), profile.degree(), way->form(), profile.form(), way->knots(), profile.knots(),
                                    way->cvCount(), profile.cvCount(), std::move(cvs), way->rational() || profile.rational(),
                                    error);
    }
    // Tube: sections of the profile carried along the path in a rotation-minimising frame, lofted.
    const int sections = std::clamp(4 * way->spans(), 8, 512);
    std::vector<NurbsCurve> curves;
    glm::dmat3 frame(1.0);
    glm::dvec3 tangentBefore(0.0);
    for (int k = 0; k <= sections; ++k) {
        const double t = way->tMin() + (way->tMax() - way->tMin()) * k / sections;
        glm::dvec3 at, tangent;
        way->evaluate(t, &at, &tangent);
        if (glm::length(tangent) > 0.0) tangent = glm::normalize(tangent);
        if (k > 0 && glm::length(tangent) > 0.0 && glm::length(tangentBefore) > 0.0) {
            const glm::dvec3 axis = glm::cross(tangentBefore, tangent);
            const double sinA = glm::length(axis), cosA = glm::dot(tangentBefore, tangent);
            if (sinA > 1e-12) {
                const glm::dvec3 n = axis / sinA;
                // Rodrigues: the rotation taking the previous tangent to this one.
                const glm::dmat3 cross(0, n.z, -n.y, -n.z, 0, n.x, n.y, -n.x, 0);
                const glm::dmat3 step = glm::dmat3(1.0) + sinA * cross + (1.0 - cosA) * (cross * cross);
                frame = step * frame;
            }
        }
        if (glm::length(tangent) > 0.0) tangentBefore = tangent;
        std::vector<glm::dvec4> cvs;
        for (const glm::dvec4& c : pc) cvs.emplace_back((at + frame * (cartesian(c) - anchor)) * c.w, c.w);
        std::optional<NurbsCurve> section =
            NurbsCurve::create(profile.degree(), profile.form(), profile.knots(), std::move(cvs), profile.rational(), error);
        if (!section) return std::nullopt;
        curves.push_back(std::move(*section));
    }
    LoftParams loft;
    loft.uniform = true;
    loft.autoReverse = false;
    return loftCurves(curves, loft, error);
}

// ---- revolve

std::optional<NurbsSurface> revolveCurve(const NurbsCurve& profile, const RevolveParams& p, std::string* error) {
    if (p.degree != 1 && p.degree != 3) return failWith(error, "degree " + std::to_string(p.degree) + " is not 1 or 3");
    if (!std::isfinite(p.startSweep) || !std::isfinite(p.endSweep)) return failWith(error, "sweep angles are not finite");
    const double sweep = std::clamp(p.endSweep - p.startSweep, -kTwoPi, kTwoPi);
    if (std::abs(sweep) < 1e-9) return failWith(error, "sweep angle is zero");
    const double axisLength = glm::length(p.axis);
    if (!std::isfinite(axisLength) || axisLength <= 0.0) return failWith(error, "axis must be a non-zero finite vector");
    if (!isFinite(p.pivot)) return failWith(error, "pivot is not finite");
    RevolveFrame f{p.axis / axisLength, p.pivot};

    double maxRadius = 0.0;
    for (const glm::dvec4& c : profile.cvs()) {
        const glm::dvec3 d = glm::dvec3(c) / c.w - f.pivot;
        maxRadius = std::max(maxRadius, glm::length(d - glm::dot(d, f.axis) * f.axis));
    }
    double extent = 0.0;
    for (const glm::dvec4& c : profile.cvs()) extent = std::max(extent, glm::length(glm::dvec3(c) / c.w - f.pivot));
    if (!std::isfinite(maxRadius) || maxRadius <= 1e-12 * std::max(extent, 1e-300)) {
        return failWith(error, "the profile lies on the axis");
    }

    const bool full = isFullTurn(sweep);
    const int minSections = full ? 3 : 1;
    int sections = p.sections;
    if (p.useTolerance) {
        if (!std::isfinite(p.tolerance) || p.tolerance <= 0.0) return failWith(error, "tolerance must be > 0");
        // The radial error shrinks as sections grow: bisect for the fewest that meet the tolerance.
        int lo = minSections, hi = kMaxSections;
        if (sweepRadialError(p.degree, sweep, hi) * maxRadius > p.tolerance) {
            lo = hi;
        } else {
            while (lo < hi) {
                const int mid = lo + (hi - lo) / 2;
                if (sweepRadialError(p.degree, sweep, mid) * maxRadius <= p.tolerance) hi = mid;
                else lo = mid + 1;
            }
        }
        sections = lo;
    }
    if (sections < minSections || sections > kMaxSections) {
        return failWith(error, "sections " + std::to_string(sections) + " outside " + std::to_string(minSections) +
                                   ".." + std::to_string(kMaxSections));
    }
    auto surface = buildRevolve(profile, f, p.degree, p.startSweep, sweep, sections, error);
    if (!surface || !p.autoCorrectNormal) return surface;
    // autoCorrectNormal: the normal in the middle of the surface should point away from the axis;
    // otherwise revolve about the reversed axis (which reverses the sweep direction).
    const double u = 0.5 * (surface->uMin() + surface->uMax()), v = 0.5 * (surface->vMin() + surface->vMax());
    const glm::dvec3 pos = surface->point(u, v);
    const glm::dvec3 d = pos - f.pivot;
    const glm::dvec3 outward = d - glm::dot(d, f.axis) * f.axis;
    if (glm::dot(surface->normal(u, v), outward) >= 0.0) return surface;
    f.axis = -f.axis;
    return buildRevolve(profile, f, p.degree, p.startSweep, sweep, sections, error);
}

// ---- loft

std::optional<NurbsSurface> loftCurves(const std::vector<NurbsCurve>& curves, const LoftParams& p, std::string* error) {
    const size_t N = curves.size();
    if (N < 2) return failWith(error, "a loft needs at least 2 curves, got " + std::to_string(N));
    if (N > kMaxLoftCurves) return failWith(error, std::to_string(N) + " loft curves exceed " + std::to_string(kMaxLoftCurves));
    if (p.degree != 1 && p.degree != 3) return failWith(error, "degree " + std::to_string(p.degree) + " is not 1 or 3");
    if (p.sectionSpans < 1 || p.sectionSpans > 1000) {
        return failWith(error, "sectionSpans " + std::to_string(p.sectionSpans) + " outside 1..1000");
    }

    std::vector<Spline> splines;
    for (const NurbsCurve& c : curves) splines.push_back(toSpline(c));
    for (size_t k = 0; k < N; ++k) {
        const bool flip = p.autoReverse ? (k > 0 && runsAgainst(splines[k], splines[k - 1]))
                                        : (k < p.reverse.size() && p.reverse[k]);
        if (flip) splines[k] = reverseSpline(std::move(splines[k]));
    }
    Sections sec = compatibleSections(std::move(splines));

    // Section parameters: uniform 0, 1, 2 …; chord length: accumulated start-point distances.
    std::vector<double> t(N + (p.close ? 1 : 0), 0.0);
    bool chord = !p.uniform;
    for (size_t k = 1; k < t.size(); ++k) {
        const Spline& a = sec.curves[k - 1];
        const Spline& b = sec.curves[k % N];
        const double dist = glm::length(evalPoint(b, b.tMin()) - evalPoint(a, a.tMin()));
        if (!(dist > 1e-12) || !std::isfinite(dist)) chord = false;
        t[k] = t[k - 1] + dist;
    }
    if (!chord)
        for (size_t k = 0; k < t.size(); ++k) t[k] = double(k);

    auto dir = interpolateSections(sec, t, p.degree, p.close, error);
    if (!dir) return std::nullopt;
    if (p.sectionSpans > 1) subdivideLoftDirection(*dir, t, p.sectionSpans);

    const size_t M = dir->rows.size(), K = dir->rows[0].size();
    std::vector<glm::dvec4> cvs;
    cvs.reserve(M * K);
    if (!p.reverseSurfaceNormals) {
        for (size_t i = 0; i < M; ++i) cvs.insert(cvs.end(), dir->rows[i].begin(), dir->rows[i].end());
    } else {
        for (size_t j = 0; j < K; ++j)
            for (size_t i = 0; i < M; ++i) cvs.push_back(dir->rows[i][j]);
    }
    const bool rational = anyRational(cvs);
    if (!p.reverseSurfaceNormals) {
        return NurbsSurface::create(dir->degree, sec.degree, dir->form, sec.form, dir->knots, sec.knots, int(M), int(K),
                                    std::move(cvs), rational, error);
    }
    return NurbsSurface::create(sec.degree, dir->degree, sec.form, dir->form, sec.knots, dir->knots, int(K), int(M),
                                std::move(cvs), rational, error);
}

// ---- tessellation

std::optional<Mesh> tessellateSurface(const NurbsSurface& s, const TessellateParams& p, std::string* error,
                                      std::vector<std::string>* notes) {
    const bool triangles = p.polygonType == 0;
    if (p.polygonType != 0 && p.polygonType != 1) {
        return failWith(error, "polygonType " + std::to_string(p.polygonType) + " is not 0 (triangles) or 1 (quads)");
    }
    const DirectionView du{s, true}, dv{s, false};
    std::vector<double> us, vs;
    std::vector<glm::dvec3> pts;
    std::vector<glm::dvec2> uvs;

    if (p.format == int(TessellationFormat::ControlPoints)) {
        if (p.matchNormalDir) note(notes, "matchNormalDir is not modelled: CV faces wind along dP/du x dP/dv");
        // A periodic direction's distinct CVs, plus one column back to the first (joined as a seam).
        const bool wrapU = s.formU() == NurbsForm::Periodic, wrapV = s.formV() == NurbsForm::Periodic;
        const size_t cu = size_t(s.cvCountU() - (wrapU ? s.degreeU() : 0));
        const size_t cv = size_t(s.cvCountV() - (wrapV ? s.degreeV() : 0));
        const size_t m = cu + (wrapU ? 1 : 0), n = cv + (wrapV ? 1 : 0);
        for (size_t j = 0; j < n; ++j)
            for (size_t i = 0; i < m; ++i) {
                pts.push_back(s.cvPoint(int(i % cu), int(j % cv)));
                uvs.emplace_back(m > 1 ? double(i) / double(m - 1) : 0.0, n > 1 ? double(j) / double(n - 1) : 0.0);
            }
        for (const glm::dvec3& q : pts)
            if (!isFinite(q)) return failWith(error, "the surface has non-finite CVs");
        return gridMesh(pts, uvs, m, n, triangles);
    }

    Refinement refine;
    if (p.format == int(TessellationFormat::General)) {
        auto grid = [&](const DirectionView& d, int type, int number, const char* name) -> std::optional<std::vector<double>> {
            if (number < 1 || number > 100000) {
                return failWith(error, std::string(name) + "Number " + std::to_string(number) + " outside 1..100000");
            }
            switch (type) {
                case int(IsoparmType::SpanEquiSpaced): return perSpanSegments(d, number + 1);
                case int(IsoparmType::SurfaceEquiSpaced): return equalSegments(d.lo(), d.hi(), number + 1);
                case int(IsoparmType::Surface3DDistance):
                    note(notes, std::string(name) + "Type 0 (3D distance) is tessellated as type 1 (equal 3D spacing)");
                    return equalLengthSegments(d, number + 1);
                case int(IsoparmType::Surface3DEquiSpaced): return equalLengthSegments(d, number + 1);
                default: return failWith(error, std::string(name) + "Type " + std::to_string(type) + " is not 0..3");
            }
        };
        auto gu = grid(du, p.uType, p.uNumber, "u");
        if (!gu) return std::nullopt;
        auto gv = grid(dv, p.vType, p.vNumber, "v");
        if (!gv) return std::nullopt;
        us = std::move(*gu);
        vs = std::move(*gv);
        refine.useChordHeight = p.useChordHeight;
        refine.chordHeight = p.chordHeight;
        refine.useRatio = p.useChordHeightRatio;
        refine.ratio = p.chordHeightRatio;
    } else if (p.format == int(TessellationFormat::StandardFit)) {
        note(notes, "format 1 (standard fit) is approximated by one segment per span refined by chordHeightRatio and delta");
        us = perSpanSegments(du, 1);
        vs = perSpanSegments(dv, 1);
        refine.useChordHeight = true;
        refine.chordHeight = p.delta;
        refine.useRatio = true;
        refine.ratio = p.chordHeightRatio;
    } else if (p.format == int(TessellationFormat::TriangleCount)) {
        if (p.polygonCount < 1 || p.polygonCount > (1 << 22)) {
            return failWith(error, "polygonCount " + std::to_string(p.polygonCount) + " outside 1..4194304");
        }
        note(notes, "format 0 (triangle count) is approximated by an equal-parameter grid of about polygonCount polygons");
        auto averageLength = [](const DirectionView& d) {
            double total = 0.0;
            for (int k = 0; k < 3; ++k) {
                const double o = d.otherLo() + (d.otherHi() - d.otherLo()) * (k + 0.5) / 3.0;
                glm::dvec3 last = d.at(d.lo(), o);
                for (int i = 1; i <= 32; ++i) {
                    const glm::dvec3 q = d.at(d.lo() + (d.hi() - d.lo()) * i / 32.0, o);
                    total += glm::length(q - last);
                    last = q;
                }
            }
            return total / 3.0;
        };
        const double lu = averageLength(du), lv = averageLength(dv);
        const double quads = triangles ? 0.5 * p.polygonCount : double(p.polygonCount);
        const double aspect = (lu > 0.0 && lv > 0.0 && std::isfinite(lu / lv)) ? lu / lv : 1.0;
        const int nu = std::clamp(int(std::lround(std::sqrt(quads * aspect))), 1, 1 << 20);
        const int nv = std::clamp(int(std::lround(quads / nu)), 1, 1 << 20);
        us = equalSegments(s.uMin(), s.uMax(), nu);
        vs = equalSegments(s.vMin(), s.vMax(), nv);
    } else {
        return failWith(error, "format " + std::to_string(p.format) + " is not 0..3");
    }
    if (refine.useChordHeight && !(std::isfinite(refine.chordHeight) && refine.chordHeight > 0.0)) {
        return failWith(error, "chord height must be finite and > 0");
    }
    if (refine.useRatio && !(std::isfinite(refine.ratio) && refine.ratio >= 0.0 && refine.ratio <= 1.0)) {
        return failWith(error, "chordHeightRatio must be in [0, 1]");
    }
    if (us.size() * vs.size() > kMaxGridPoints) return failWith(error, "the tessellation grid exceeds 4M points");
    if (refine.active()) {
        bool refined = false;
        for (int pass = 0; pass < kMaxRefinePasses; ++pass) {
            const bool a = refineOnce(du, us, vs, refine);
            const bool b = refineOnce(dv, vs, us, refine);
            if (us.size() * vs.size() > kMaxGridPoints) return failWith(error, "the refined grid exceeds 4M points");
            refined = refined || a || b;
            if (!a && !b) break;
        }
        if (refined) note(notes, "chord height refinement halves whole grid lines (Maya refines per polygon)");
    }

    const size_t m = us.size(), n = vs.size();
    pts.reserve(m * n);
    uvs.reserve(m * n);
    const double ru = s.uMax() - s.uMin(), rv = s.vMax() - s.vMin();
    for (size_t j = 0; j < n; ++j)
        for (size_t i = 0; i < m; ++i) {
            const glm::dvec3 q = s.point(us[i], vs[j]);
            if (!isFinite(q)) return failWith(error, "the surface evaluates to NaN/Inf");
            pts.push_back(q);
            uvs.emplace_back(ru > 0 ? (us[i] - s.uMin()) / ru : 0.0, rv > 0 ? (vs[j] - s.vMin()) / rv : 0.0);
        }
    return gridMesh(pts, uvs, m, n, triangles);
}

}  // namespace pushpin::geom
