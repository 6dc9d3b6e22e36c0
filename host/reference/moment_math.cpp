// Double-precision (long double where it helps) reference of the moment math. Written
// from docs/math.md and Peters, HPG 2017 without looking at kernels/*.clh: different formulas where the
// papers offer them (xi4 by Eq. 1, Gaussian elimination instead of Cholesky, bit layouts by
// arithmetic instead of shifts).
#include "reference/moment_math.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace msmcl::reference {

namespace {

using Real = long double;

// Solves the 3x3 system m x = rhs by Gaussian elimination with partial pivoting.
// Returns false if a pivot vanishes.
bool solve3(Real m[3][3], Real rhs[3], Real x[3]) {
    for (int col = 0; col < 3; ++col) {
        // Largest pivot of this column moves up.
        int pivot = col;
        for (int row = col + 1; row < 3; ++row)
            if (std::fabs(m[row][col]) > std::fabs(m[pivot][col])) pivot = row;
        if (m[pivot][col] == 0) return false;
        if (pivot != col) {
            for (int k = 0; k < 3; ++k) std::swap(m[pivot][k], m[col][k]);
            std::swap(rhs[pivot], rhs[col]);
        }
        // Eliminate below.
        for (int row = col + 1; row < 3; ++row) {
            Real factor = m[row][col] / m[col][col];
            for (int k = col; k < 3; ++k) m[row][k] -= factor * m[col][k];
            rhs[row] -= factor * rhs[col];
        }
    }
    // Back substitution.
    for (int row = 2; row >= 0; --row) {
        Real sum = rhs[row];
        for (int k = row + 1; k < 3; ++k) sum -= m[row][k] * x[k];
        x[row] = sum / m[row][row];
    }
    return true;
}

// Share of a distribution with at most two points strictly below zf, and at zf.
Bounds discrete_bounds(Real y1, Real y2, Real v2, Real zf) {
    Bounds bounds;
    Real below = 0, at = 0;
    if (y1 < zf) below += 1 - v2;
    if (y1 == zf) at += 1 - v2;
    if (y2 < zf) below += v2;
    if (y2 == zf) at += v2;
    bounds.lower = static_cast<double>(below);
    bounds.upper = static_cast<double>(below + at);
    return bounds;
}

std::uint16_t code_nearest(double x, double max_code) {
    double q = std::floor(x * max_code + 0.5);
    return static_cast<std::uint16_t>(std::clamp(q, 0.0, max_code));
}

std::uint16_t code_up(double x, double max_code) {
    double q = std::ceil(x * max_code);
    return static_cast<std::uint16_t>(std::clamp(q, 0.0, max_code));
}

const double sqrt3 = std::sqrt(3.0);
const double psi_l0 = std::log(std::log(1.2));
const double psi_l1 = std::log(std::log(2.5e6));

} // namespace

double internal_depth(double d, bool depth_range_zero_one) {
    return depth_range_zero_one ? 2.0 * d - 1.0 : d;
}

Moments moments_of(double z) {
    return {z, z * z, z * z * z, z * z * z * z};
}

Moments moments_of(const Distribution& distribution) {
    Real total = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0;
    for (std::size_t i = 0; i < distribution.depth.size(); ++i) {
        Real z = distribution.depth[i], w = distribution.weight[i];
        total += w;
        s1 += w * z;
        s2 += w * z * z;
        s3 += w * z * z * z;
        s4 += w * z * z * z * z;
    }
    return {static_cast<double>(s1 / total), static_cast<double>(s2 / total),
            static_cast<double>(s3 / total), static_cast<double>(s4 / total)};
}

Moments bias(const Moments& b, double alpha, double bstar) {
    return {(1 - alpha) * b.b1, (1 - alpha) * b.b2 + alpha * bstar, (1 - alpha) * b.b3,
            (1 - alpha) * b.b4 + alpha * bstar};
}

Moments unshift(const Moments& m, double c) {
    Real b1 = m.b1, b2 = m.b2, b3 = m.b3, b4 = m.b4, k = c;
    // E (u + c)^n with u = z - c.
    return {static_cast<double>(b1 + k), static_cast<double>(b2 + 2 * k * b1 + k * k),
            static_cast<double>(b3 + 3 * k * b2 + 3 * k * k * b1 + k * k * k),
            static_cast<double>(b4 + 4 * k * b3 + 6 * k * k * b2 + 4 * k * k * k * b1 + k * k * k * k)};
}

Moments shift(const Moments& b, double c) { return unshift(b, -c); }

Nlq nlq_from_moments(const Moments& biased) {
    Real b1 = biased.b1, b2 = biased.b2, b3 = biased.b3, b4 = biased.b4;
    // The quadratic whose roots are the two depths.
    Real q2 = b2 - b1 * b1;
    Real q1 = b1 * b2 - b3;
    Real q0 = -b1 * q1 - b2 * q2;
    Real discriminant = q1 * q1 - 4 * q2 * q0;
    if (!(q2 > 1e-300L) || !(discriminant > 0)) return {biased.b1, biased.b1, 0.5, 0.0};
    Real root = std::sqrt(discriminant);
    Real y1 = (-q1 - root) / (2 * q2);
    Real y2 = (-q1 + root) / (2 * q2);
    if (y1 > y2) std::swap(y1, y2);
    Real v2 = (b1 - y1) / (y2 - y1);
    // Eq. 1: offset of b4 against the two-point distribution.
    Real xi4 = b4 - (1 - v2) * y1 * y1 * y1 * y1 - v2 * y2 * y2 * y2 * y2;
    return {static_cast<double>(y1), static_cast<double>(y2), static_cast<double>(v2),
            static_cast<double>(xi4)};
}

Moments moments_from_nlq(const Nlq& nlq) {
    Moments a = moments_of(nlq.y1), b = moments_of(nlq.y2);
    double v1 = 1 - nlq.v2, v2 = nlq.v2;
    return {v1 * a.b1 + v2 * b.b1, v1 * a.b2 + v2 * b.b2, v1 * a.b3 + v2 * b.b3,
            v1 * a.b4 + v2 * b.b4 + nlq.xi4};
}

double psi4(double xi4) {
    double xi = std::max(1.2e-7, std::min(xi4, 0.25));
    return (std::log(std::log(xi * 1e7)) - psi_l0) / (psi_l1 - psi_l0);
}

double psi4_inverse(double psi) { return std::exp(std::exp(psi * (psi_l1 - psi_l0) + psi_l0)) / 1e7; }

std::array<double, 4> msm64_affine(const Moments& b) {
    return {1.5 * b.b1 - 2 * b.b3 + 0.5, 4 * b.b2 - 4 * b.b4,
            sqrt3 * (b.b1 / 2 - 2 * b.b3 / 9) + 0.5, 0.5 * b.b2 + 0.5 * b.b4};
}

Moments msm64_affine_inverse(const std::array<double, 4>& rgba) {
    double r = rgba[0] - 0.5, g = rgba[1], bl = rgba[2] - 0.5, a = rgba[3];
    return {-r / 3 + sqrt3 * bl, 0.125 * g + a, -0.75 * r + 0.75 * sqrt3 * bl, -0.125 * g + a};
}

std::array<std::uint32_t, 2> pack_codes16(const Codes16& codes) {
    return {static_cast<std::uint32_t>(codes[0] + 65536u * codes[1]),
            static_cast<std::uint32_t>(codes[2] + 65536u * codes[3])};
}

Codes16 unpack_codes16(const std::array<std::uint32_t, 2>& words) {
    return {static_cast<std::uint16_t>(words[0] % 65536u), static_cast<std::uint16_t>(words[0] / 65536u),
            static_cast<std::uint16_t>(words[1] % 65536u), static_cast<std::uint16_t>(words[1] / 65536u)};
}

Codes16 encode_msm64(const Moments& b) {
    std::array<double, 4> rgba = msm64_affine(b);
    return {code_nearest(rgba[0], 65535), code_nearest(rgba[1], 65535), code_nearest(rgba[2], 65535),
            code_nearest(rgba[3], 65535)};
}

Moments decode_msm64(const Codes16& codes) {
    return msm64_affine_inverse({codes[0] / 65535.0, codes[1] / 65535.0, codes[2] / 65535.0,
                                 codes[3] / 65535.0});
}

Codes16 encode_nlq64(const Nlq& nlq) {
    return {code_nearest((nlq.y1 + 1) / 2, 65535), code_nearest((nlq.y2 + 1) / 2, 65535),
            code_nearest(nlq.v2, 65535), code_up(psi4(nlq.xi4), 65535)};
}

Nlq decode_nlq64(const Codes16& codes) {
    return {codes[0] / 65535.0 * 2 - 1, codes[1] / 65535.0 * 2 - 1, codes[2] / 65535.0,
            psi4_inverse(codes[3] / 65535.0)};
}

Nlq32Fields nlq32_fields(const Nlq& nlq) {
    Nlq32Fields fields;
    fields.psi = code_up(psi4(nlq.xi4), 63);
    fields.sqrt_v2 = code_nearest(std::sqrt(std::max(nlq.v2, 0.0)), 127);
    auto depth_code = [](double y) {
        return static_cast<std::uint32_t>(std::clamp(std::floor(511.5 * (y + 1)), 0.0, 1022.0));
    };
    std::uint32_t yt1 = depth_code(nlq.y1);
    std::uint32_t yt2 = std::max(depth_code(nlq.y2), yt1);
    // Rotate the upper half of the triangle yt1 <= yt2 by 180 degrees.
    bool fold = yt1 >= 512;
    fields.t1 = fold ? 1023 - yt1 : yt1;
    fields.t2 = fold ? 1022 - yt2 : yt2;
    return fields;
}

std::uint32_t pack_nlq32(const Nlq32Fields& f) {
    // Bits 0-5, 6-12, 13-21, 22-31 as place values.
    std::uint64_t word = f.psi + 64ull * f.sqrt_v2 + 8192ull * f.t1 + 4194304ull * f.t2;
    if (f.psi > 63 || f.sqrt_v2 > 127 || f.t1 > 511 || f.t2 > 1023)
        throw std::logic_error("nlq32 field out of range");
    return static_cast<std::uint32_t>(word);
}

Nlq32Fields unpack_nlq32(std::uint32_t word) {
    Nlq32Fields f;
    f.psi = word % 64;
    f.sqrt_v2 = (word / 64) % 128;
    f.t1 = (word / 8192) % 512;
    f.t2 = word / 4194304;
    return f;
}

std::uint32_t encode_nlq32(const Nlq& nlq) { return pack_nlq32(nlq32_fields(nlq)); }

Nlq decode_nlq32(std::uint32_t word) {
    Nlq32Fields f = unpack_nlq32(word);
    bool folded = f.t2 < f.t1;
    double yt1 = folded ? 1023.0 - f.t1 : f.t1;
    double yt2 = folded ? 1022.0 - f.t2 : f.t2;
    double sqrt_v2 = f.sqrt_v2 / 127.0;
    return {(yt1 + 0.5) / 511.5 - 1, (yt2 + 0.5) / 511.5 - 1, sqrt_v2 * sqrt_v2, psi4_inverse(f.psi / 63.0)};
}

Bounds hamburger4(const Moments& biased, double zf_in) {
    Real zf = zf_in;
    // At most two points of support (singular Hankel matrix): the distribution is unique.
    Nlq two_point = nlq_from_moments(biased);
    if (two_point.y1 == two_point.y2 || two_point.xi4 <= 1e-12)
        return discrete_bounds(two_point.y1, two_point.y2, two_point.v2, zf);
    // (1)-(2) Hankel system B q = (1, zf, zf^2).
    Real hankel[3][3] = {{1, biased.b1, biased.b2}, {biased.b1, biased.b2, biased.b3},
                         {biased.b2, biased.b3, biased.b4}};
    Real rhs[3] = {1, zf, zf * zf};
    Real q[3];
    if (!solve3(hankel, rhs, q)) throw std::runtime_error("hamburger4: singular Hankel matrix");
    // (3) The other support points: roots of q2 z^2 + q1 z + q0 (a vanishing q2 leaves one).
    Real z[3] = {zf, 0, 0};
    Real scale = std::max(std::fabs(q[1]), std::fabs(q[0]));
    int points = 3;
    if (std::fabs(q[2]) <= 1e-15L * scale) {
        z[1] = -q[0] / q[1];
        points = 2;
    } else {
        Real discriminant = std::max(q[1] * q[1] - 4 * q[2] * q[0], Real(0));
        Real t = -0.5L * (q[1] + (q[1] >= 0 ? std::sqrt(discriminant) : -std::sqrt(discriminant)));
        z[1] = t / q[2];
        z[2] = q[0] / t;
    }
    // (4) Weights: Vandermonde system for (b0, b1, b2).
    Real w[3] = {0, 0, 0};
    if (points == 3) {
        Real vandermonde[3][3] = {{1, 1, 1}, {z[0], z[1], z[2]}, {z[0] * z[0], z[1] * z[1], z[2] * z[2]}};
        Real moments[3] = {1, biased.b1, biased.b2};
        if (!solve3(vandermonde, moments, w)) throw std::runtime_error("hamburger4: singular Vandermonde");
    } else {
        w[1] = (biased.b1 - z[0]) / (z[1] - z[0]);
        w[0] = 1 - w[1];
    }
    // (5) Lower bound: weights of the points below zf; upper adds the weight at zf.
    Real lower = 0;
    for (int l = 1; l < points; ++l)
        if (z[l] < zf) lower += w[l];
    Bounds bounds;
    bounds.lower = static_cast<double>(lower);
    bounds.upper = static_cast<double>(lower + w[0]);
    return bounds;
}

double nlq_shadow(const Nlq& nlq, double zf, bool algorithm3_clamps) {
    Nlq texel = nlq;
    if (algorithm3_clamps) {
        texel.y2 = std::max(texel.y2, texel.y1 + 1e-6);
        texel.v2 = std::clamp(texel.v2, 1e-6, 1 - 1e-6);
    }
    return hamburger4(moments_from_nlq(texel), zf).lower;
}

double exact_shadow(const Distribution& distribution, double zf) {
    Real total = 0, below = 0;
    for (std::size_t i = 0; i < distribution.depth.size(); ++i) {
        total += distribution.weight[i];
        if (distribution.depth[i] < zf) below += distribution.weight[i];
    }
    return static_cast<double>(below / total);
}

} // namespace msmcl::reference
