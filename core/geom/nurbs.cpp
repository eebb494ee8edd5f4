// core/geom/nurbs.cpp: knot handling, basis functions and evaluation of NURBS curves and surfaces.
// Algorithms follow Piegl & Tiller, "The NURBS Book" (2nd ed.): span search A2.1, basis functions
// A2.2, their first derivatives from the degree − 1 functions (eq. 2.7), rational derivatives
// (eq. 4.8 and 4.20).
#include "core/geom/nurbs.h"

#include "core/util/format.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pushpin::geom {

namespace {

// Moves t into the domain [lo, hi]: wrapped for periodic directions, clamped otherwise. Non-finite
// parameters map to lo so that evaluation never leaves the knot vector.
double normalizeParameter(double t, double lo, double hi, NurbsForm form) {
    if (!std::isfinite(t)) return lo;
    if (form == NurbsForm::Periodic && hi > lo && (t < lo || t > hi)) {
        double period = hi - lo;
        double r = std::fmod(t - lo, period);
        if (r < 0.0) r += period;
        return lo + r;
    }
    return std::clamp(t, lo, hi);
}

std::string validateCvs(const std::vector<glm::dvec4>& cvs, int cvCountV) {
    for (size_t k = 0; k < cvs.size(); ++k) {
        const glm::dvec4& c = cvs[k];
        bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(c.w);
        std::string where = cvCountV > 0 ? "CV [" + std::to_string(k / size_t(cvCountV)) + "][" +
                                               std::to_string(k % size_t(cvCountV)) + "]"
                                         : "CV " + std::to_string(k);
        if (!finite) return where + " is not finite";
        if (!(c.w > 0.0)) return where + " has weight " + util::formatNumber(c.w) + " (weights must be > 0)";
    }
    return {};
}

}  // namespace

const char* nurbsFormName(NurbsForm form) {
    switch (form) {
        case NurbsForm::Open: return "open";
        case NurbsForm::Closed: return "closed";
        case NurbsForm::Periodic: return "periodic";
    }
    return "unknown";
}

std::vector<double> textbookKnotsFromMaya(const std::vector<double>& mayaKnots, int degree, NurbsForm form) {
    std::vector<double> out;
    if (mayaKnots.empty()) return out;
    const size_t n = mayaKnots.size();
    out.reserve(n + 2);
    double first = mayaKnots.front();
    double last = mayaKnots.back();
    if (form == NurbsForm::Periodic && n >= 2) {
        // Textbook vector t[0..n+1] with t[i] = mayaKnots[i-1]; n + 1 − 2·degree spans.
        const long spans = long(n) + 1 - 2L * degree;
        auto t = [&](long i) { return mayaKnots[size_t(i - 1)]; };
        const long m = long(n);  // index of the last Maya knot in textbook numbering
        if (spans >= 1 && 1 + spans <= m && m - spans >= 1) {
            first = t(1) - (t(1 + spans) - t(spans));
            last = t(m) + (t(m + 1 - spans) - t(m - spans));
        } else {
            first = t(1) - (t(2) - t(1));
            last = t(m) + (t(m) - t(m - 1));
        }
    }
    out.push_back(first);
    out.insert(out.end(), mayaKnots.begin(), mayaKnots.end());
    out.push_back(last);
    return out;
}

std::vector<double> mayaKnotsFromTextbook(const std::vector<double>& knots) {
    if (knots.size() <= 2) return {};
    return std::vector<double>(knots.begin() + 1, knots.end() - 1);
}

std::string validateKnots(const std::vector<double>& knots, int degree, int cvCount, const char* direction) {
    const std::string dir = direction;
    if (degree < 1 || degree > kMaxNurbsDegree) {
        return dir + " degree " + std::to_string(degree) + " is outside 1.." + std::to_string(kMaxNurbsDegree);
    }
    if (cvCount < degree + 1) {
        return dir + ": " + std::to_string(cvCount) + " CVs are too few for degree " + std::to_string(degree) +
               " (need at least " + std::to_string(degree + 1) + ")";
    }
    const size_t expected = size_t(cvCount) + size_t(degree) + 1;
    if (knots.size() != expected) {
        return dir + ": " + std::to_string(knots.size()) + " knots, expected " + std::to_string(expected) + " (" +
               std::to_string(cvCount) + " CVs + degree " + std::to_string(degree) + " + 1)";
    }
    for (size_t i = 0; i < knots.size(); ++i) {
        if (!std::isfinite(knots[i])) return dir + ": knot " + std::to_string(i) + " is not finite";
        if (i > 0 && knots[i] < knots[i - 1]) {
            return dir + ": knots decrease at index " + std::to_string(i) + " (" + util::formatNumber(knots[i - 1]) +
                   " > " + util::formatNumber(knots[i]) + ")";
        }
    }
    if (!(knots[size_t(degree)] < knots[size_t(cvCount)])) {
        return dir + ": empty parameter domain [" + util::formatNumber(knots[size_t(degree)]) + ", " +
               util::formatNumber(knots[size_t(cvCount)]) + "]";
    }
    return {};
}

int findKnotSpan(int degree, const std::vector<double>& knots, int cvCount, double t) {
    const int n = cvCount;  // domain is [knots[degree], knots[n]]
    if (t >= knots[size_t(n)]) {
        int i = n - 1;
        while (i > degree && knots[size_t(i)] == knots[size_t(i) + 1]) --i;
        return i;
    }
    if (t <= knots[size_t(degree)]) {
        int i = degree;
        while (i < n - 1 && knots[size_t(i)] == knots[size_t(i) + 1]) ++i;
        return i;
    }
    auto begin = knots.begin() + degree;
    auto end = knots.begin() + n + 1;
    auto it = std::upper_bound(begin, end, t);  // first knot > t, in (degree, n]
    return int(it - knots.begin()) - 1;
}

void basisFunctions(int span, double t, int degree, const std::vector<double>& knots, double* out,
                    double* derivs) {
    double left[kMaxNurbsDegree + 1];
    double right[kMaxNurbsDegree + 1];
    const double* U = knots.data();
    out[0] = 1.0;
    if (derivs && degree == 0) derivs[0] = 0.0;
    for (int j = 1; j <= degree; ++j) {
        if (j == degree && derivs) {
            // out[0..degree-1] hold the degree − 1 functions N[span−degree+1 .. span]; eq. 2.7.
            const int p = degree;
            for (int r = 0; r <= p; ++r) {
                double a = 0.0, b = 0.0;
                if (r >= 1) a = out[r - 1] / (U[span + r] - U[span - p + r]);
                if (r <= p - 1) b = out[r] / (U[span + r + 1] - U[span - p + r + 1]);
                derivs[r] = p * (a - b);
            }
        }
        left[j] = t - U[span + 1 - j];
        right[j] = U[span + j] - t;
        double saved = 0.0;
        for (int r = 0; r < j; ++r) {
            double temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
}

glm::dvec3 NurbsSurfacePoint::normal() const {
    glm::dvec3 n = glm::cross(dPdu, dPdv);
    double len = glm::length(n);
    return len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
}

// ---------------------------------------------------------------- NurbsCurve

std::optional<NurbsCurve> NurbsCurve::create(int degree, NurbsForm form, std::vector<double> knots,
                                             std::vector<glm::dvec4> cvs, bool rational, std::string* error) {
    std::string msg = validateKnots(knots, degree, int(cvs.size()), "curve");
    if (msg.empty()) msg = validateCvs(cvs, 0);
    if (!msg.empty()) {
        if (error) *error = msg;
        return std::nullopt;
    }
    NurbsCurve c;
    c.m_degree = degree;
    c.m_form = form;
    c.m_rational = rational;
    c.m_knots = std::move(knots);
    c.m_cvs = std::move(cvs);
    return c;
}

double NurbsCurve::normalizedParameter(double t) const { return normalizeParameter(t, tMin(), tMax(), m_form); }

void NurbsCurve::evaluate(double t, glm::dvec3* position, glm::dvec3* derivative) const {
    t = normalizedParameter(t);
    double N[kMaxNurbsDegree + 1], dN[kMaxNurbsDegree + 1];
    const int span = findKnotSpan(m_degree, m_knots, cvCount(), t);
    basisFunctions(span, t, m_degree, m_knots, N, dN);
    glm::dvec4 a(0.0), da(0.0);
    for (int k = 0; k <= m_degree; ++k) {
        const glm::dvec4& p = m_cvs[size_t(span - m_degree + k)];
        a += N[k] * p;
        da += dN[k] * p;
    }
    glm::dvec3 pos = glm::dvec3(a) / a.w;
    if (position) *position = pos;
    if (derivative) *derivative = (glm::dvec3(da) - da.w * pos) / a.w;
}

glm::dvec3 NurbsCurve::point(double t) const {
    glm::dvec3 p;
    evaluate(t, &p, nullptr);
    return p;
}

Bounds3 NurbsCurve::bounds() const {
    Bounds3 b;
    for (const glm::dvec4& c : m_cvs) b.extend(glm::dvec3(c) / c.w);
    return b;
}

// ---------------------------------------------------------------- NurbsSurface

std::optional<NurbsSurface> NurbsSurface::create(int degreeU, int degreeV, NurbsForm formU, NurbsForm formV,
                                                 std::vector<double> knotsU, std::vector<double> knotsV,
                                                 int cvCountU, int cvCountV, std::vector<glm::dvec4> cvs,
                                                 bool rational, std::string* error) {
    std::string msg = validateKnots(knotsU, degreeU, cvCountU, "U");
    if (msg.empty()) msg = validateKnots(knotsV, degreeV, cvCountV, "V");
    if (msg.empty() && cvs.size() != size_t(cvCountU) * size_t(cvCountV)) {
        msg = std::to_string(cvs.size()) + " CVs, expected " + std::to_string(cvCountU) + " × " +
              std::to_string(cvCountV) + " = " + std::to_string(size_t(cvCountU) * size_t(cvCountV));
    }
    if (msg.empty()) msg = validateCvs(cvs, cvCountV);
    if (!msg.empty()) {
        if (error) *error = msg;
        return std::nullopt;
    }
    NurbsSurface s;
    s.m_degreeU = degreeU;
    s.m_degreeV = degreeV;
    s.m_formU = formU;
    s.m_formV = formV;
    s.m_rational = rational;
    s.m_knotsU = std::move(knotsU);
    s.m_knotsV = std::move(knotsV);
    s.m_cvCountU = cvCountU;
    s.m_cvCountV = cvCountV;
    s.m_cvs = std::move(cvs);
    return s;
}

glm::dvec3 NurbsSurface::cvPoint(int i, int j) const {
    const glm::dvec4& c = cv(i, j);
    return glm::dvec3(c) / c.w;
}

double NurbsSurface::clampU(double u) const { return normalizeParameter(u, uMin(), uMax(), m_formU); }
double NurbsSurface::clampV(double v) const { return normalizeParameter(v, vMin(), vMax(), m_formV); }

NurbsSurfacePoint NurbsSurface::evaluate(double u, double v) const {
    u = clampU(u);
    v = clampV(v);
    double Nu[kMaxNurbsDegree + 1], dNu[kMaxNurbsDegree + 1];
    double Nv[kMaxNurbsDegree + 1], dNv[kMaxNurbsDegree + 1];
    const int su = findKnotSpan(m_degreeU, m_knotsU, m_cvCountU, u);
    const int sv = findKnotSpan(m_degreeV, m_knotsV, m_cvCountV, v);
    basisFunctions(su, u, m_degreeU, m_knotsU, Nu, dNu);
    basisFunctions(sv, v, m_degreeV, m_knotsV, Nv, dNv);

    // Homogeneous sums A = Σ Nu Nv P, Au = Σ Nu' Nv P, Av = Σ Nu Nv' P.
    glm::dvec4 a(0.0), au(0.0), av(0.0);
    for (int k = 0; k <= m_degreeU; ++k) {
        const int i = su - m_degreeU + k;
        glm::dvec4 row(0.0), rowDv(0.0);
        for (int l = 0; l <= m_degreeV; ++l) {
            const glm::dvec4& p = cv(i, sv - m_degreeV + l);
            row += Nv[l] * p;
            rowDv += dNv[l] * p;
        }
        a += Nu[k] * row;
        au += dNu[k] * row;
        av += Nu[k] * rowDv;
    }
    NurbsSurfacePoint out;
    out.position = glm::dvec3(a) / a.w;
    out.dPdu = (glm::dvec3(au) - au.w * out.position) / a.w;
    out.dPdv = (glm::dvec3(av) - av.w * out.position) / a.w;
    return out;
}

glm::dvec3 NurbsSurface::point(double u, double v) const { return evaluate(u, v).position; }

glm::dvec3 NurbsSurface::normal(double u, double v) const {
    u = clampU(u);
    v = clampV(v);
    NurbsSurfacePoint p = evaluate(u, v);
    glm::dvec3 n = glm::cross(p.dPdu, p.dPdv);
    const double scale = glm::length(p.dPdu) * glm::length(p.dPdv);
    if (glm::length(n) > 1e-12 * scale && scale > 0.0) return glm::normalize(n);
    // Degenerate point (collapsed row of CVs): step towards the middle of the domain, where the
    // surface is regular, and use the normal there (the limit of the normals for a smooth pole).
    const double du = 1e-7 * (uMax() - uMin()) * (u < 0.5 * (uMin() + uMax()) ? 1.0 : -1.0);
    const double dv = 1e-7 * (vMax() - vMin()) * (v < 0.5 * (vMin() + vMax()) ? 1.0 : -1.0);
    for (int attempt = 0; attempt < 3; ++attempt) {
        const double u2 = u + (attempt != 1 ? du : 0.0);
        const double v2 = v + (attempt != 0 ? dv : 0.0);
        glm::dvec3 n2 = evaluate(u2, v2).normal();
        if (n2 != glm::dvec3(0.0)) return n2;
    }
    return glm::dvec3(0.0);
}

Bounds3 NurbsSurface::bounds() const {
    Bounds3 b;
    for (const glm::dvec4& c : m_cvs) b.extend(glm::dvec3(c) / c.w);
    return b;
}

}  // namespace pushpin::geom
