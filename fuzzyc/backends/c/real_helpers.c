/*
 * The float/double headers' helpers that do not depend on the rule base, in sections.  A header
 * pastes the sections it needs with the stand-in prefixes fuzzyc_ / FUZZYC_ replaced by its own
 * (NAME_min, NAME_ACTIVATION_FLOOR), so it stays one self-contained file and two headers can
 * share a translation unit.  The real type enters through one type macro: the stand-in type
 * fuzzyc_real becomes the header's own `typedef float NAME_real;` (or double).  The constants a
 * section uses are macros the header defines before it (their values belong to the model or the
 * real type): FUZZYC_ACTIVATION_FLOOR (common), FUZZYC_SQRT (bisector), FUZZYC_TOP_SHARE (mom).
 * The literals here are small integers, exact in either type; x / 2 and 0.5 * x round the same.
 * Compiles alone: gcc -std=c99 -DFUZZYC_REAL_TYPE=float -DFUZZYC_SQRT=sqrtf -c real_helpers.c
 */
#include <math.h>
#ifndef FUZZYC_REAL_TYPE
#define FUZZYC_REAL_TYPE double
#endif
#ifndef FUZZYC_SQRT
#define FUZZYC_SQRT sqrt
#endif
typedef FUZZYC_REAL_TYPE fuzzyc_real;
#define FUZZYC_ACTIVATION_FLOOR ((fuzzyc_real)1e-12)
#define FUZZYC_TOP_SHARE ((fuzzyc_real)0.999999)
/* -- section: common -- */
/* min/max that propagate NaN, like numpy (fmin/fmax would drop it). */
static inline fuzzyc_real fuzzyc_min(fuzzyc_real a, fuzzyc_real b) { return (a < b || a != a) ? a : b; }
static inline fuzzyc_real fuzzyc_max(fuzzyc_real a, fuzzyc_real b) { return (a > b || a != a) ? a : b; }
static inline fuzzyc_real fuzzyc_sign(fuzzyc_real a) { return a > 0 ? 1 : (a < 0 ? -1 : a); }
/* NaN-free helpers for values known to be numbers. */
static inline fuzzyc_real fuzzyc_lesser(fuzzyc_real a, fuzzyc_real b) { return a < b ? a : b; }
static inline fuzzyc_real fuzzyc_greater(fuzzyc_real a, fuzzyc_real b) { return a > b ? a : b; }
static inline fuzzyc_real fuzzyc_clamp(fuzzyc_real x, fuzzyc_real lo, fuzzyc_real hi) { return x < lo ? lo : (x > hi ? hi : x); }
/* An activation below the floor does not fire (fuzzyc.semantics.model.ACTIVATION_FLOOR). */
static inline fuzzyc_real fuzzyc_fired(fuzzyc_real a) { return a < FUZZYC_ACTIVATION_FLOOR ? 0 : a; }
static inline void fuzzyc_order(fuzzyc_real *a, fuzzyc_real *b) { fuzzyc_real lo = fuzzyc_lesser(*a, *b); *b = fuzzyc_greater(*a, *b); *a = lo; }
static inline fuzzyc_real fuzzyc_ratio_or(fuzzyc_real num, fuzzyc_real den, fuzzyc_real fallback) { return den != 0 ? num / den : fallback; }
/* One linear piece of M: exact area and first moment. */
static inline void fuzzyc_piece(fuzzyc_real x0, fuzzyc_real x1, fuzzyc_real f0, fuzzyc_real f1, fuzzyc_real *area, fuzzyc_real *moment) {
    fuzzyc_real dx = x1 - x0;
    *area += (f0 + f1) / 2 * dx;
    *moment += dx * (f0 * (2 * x0 + x1) + f1 * (x0 + 2 * x1)) / 6;
}
/* Trapezoid row: a b c d 1/(b-a) 1/(d-c); shoulders have a = b = -inf or c = d = +inf. */
static inline fuzzyc_real fuzzyc_trapezoid(fuzzyc_real x, const fuzzyc_real q[6]) {
    fuzzyc_real rise = x >= q[1] ? 1 : (x > q[0] ? (x - q[0]) * q[4] : 0);
    fuzzyc_real fall = x <= q[2] ? 1 : (x < q[3] ? (q[3] - x) * q[5] : 0);
    return rise < fall ? rise : fall;
}
/* An input that is not a number counts as 0 where a number is needed. */
static inline fuzzyc_real fuzzyc_number_or_zero(fuzzyc_real v) { return v == v ? v : 0; }
/* -- section: points -- */
/* The points of M, (u, f) with M linear between them: the i-th of a stored polygon or of the grid. */
typedef void (*fuzzyc_points)(const fuzzyc_real *c, int i, fuzzyc_real *u, fuzzyc_real *f);
/* -- section: polygon -- */
static inline void fuzzyc_polygon_point(const fuzzyc_real *c, int i, fuzzyc_real *u, fuzzyc_real *f) { *u = c[2 * i]; *f = c[2 * i + 1]; }
static inline void fuzzyc_store(fuzzyc_real *poly, const fuzzyc_real *u, const fuzzyc_real *f, int n) {
    int i;
    for (i = 0; i < n; ++i) { poly[2 * i] = u[i]; poly[2 * i + 1] = f[i]; }
}
/* -- section: sums -- */
/* Compensated (Kahan) sums: 2000 grid pieces summed in float would lose ~1e-5 of the range. */
static inline void fuzzyc_add_piece(fuzzyc_real u0, fuzzyc_real u1, fuzzyc_real f0, fuzzyc_real f1, fuzzyc_real sum[4]) {
    fuzzyc_real piece[2] = {0, 0};
    int k;
    fuzzyc_piece(u0, u1, f0, f1, &piece[0], &piece[1]);
    for (k = 0; k < 2; ++k) {   /* sum[k] with its compensation sum[k + 2] */
        fuzzyc_real y = piece[k] - sum[k + 2], s = sum[k] + y;
        sum[k + 2] = (s - sum[k]) - y;
        sum[k] = s;
    }
}
/* Area and moment of the first n points into sum[0], sum[1]; stops early (returns the piece's index) once the area would reach `stop`. */
static inline int fuzzyc_integrate(fuzzyc_points at, const fuzzyc_real *c, int n, fuzzyc_real stop, fuzzyc_real sum[4]) {
    fuzzyc_real u0, f0, u1, f1;
    int i;
    at(c, 0, &u0, &f0);
    for (i = 1; i < n; ++i) {
        at(c, i, &u1, &f1);
        if ((f0 + f1) / 2 * (u1 - u0) + sum[0] >= stop) return i;
        fuzzyc_add_piece(u0, u1, f0, f1, sum);
        u0 = u1; f0 = f1;
    }
    return n;
}
/* -- section: centroid -- */
static inline fuzzyc_real fuzzyc_centroid_of(fuzzyc_points at, const fuzzyc_real *c, int n, fuzzyc_real fallback) {
    fuzzyc_real sum[4] = {0, 0, 0, 0};
    fuzzyc_integrate(at, c, n, INFINITY, sum);
    return sum[0] > 0 ? sum[1] / sum[0] : fallback;
}
/* -- section: bisector -- */
/* Bisector: the leftmost u where the running area reaches half the area, solved in its piece: g0 t + slope t^2 / 2 = rem, in a form stable for slope 0. */
static inline fuzzyc_real fuzzyc_bisect_piece(fuzzyc_real u0, fuzzyc_real d, fuzzyc_real g0, fuzzyc_real g1, fuzzyc_real rem) {
    fuzzyc_real slope = d > 0 ? (g1 - g0) / d : 0;
    fuzzyc_real den = g0 + FUZZYC_SQRT(fuzzyc_greater(g0 * g0 + 2 * slope * rem, 0));
    fuzzyc_real t = den > 0 ? 2 * rem / den : 0;
    return u0 + fuzzyc_clamp(t, 0, d);
}
static inline fuzzyc_real fuzzyc_bisector_of(fuzzyc_points at, const fuzzyc_real *c, int n, fuzzyc_real fallback) {
    fuzzyc_real sum[4] = {0, 0, 0, 0}, half, u0, f0, u1, f1;
    int i;
    fuzzyc_integrate(at, c, n, INFINITY, sum);
    half = sum[0] / 2;
    if (!(half > 0)) return fallback;
    sum[0] = sum[1] = sum[2] = sum[3] = 0;
    i = fuzzyc_integrate(at, c, n, half, sum);
    if (i >= n) { at(c, n - 1, &u0, &f0); return u0; }   /* rounding: the end */
    at(c, i - 1, &u0, &f0);
    at(c, i, &u1, &f1);
    return fuzzyc_bisect_piece(u0, u1 - u0, f0, f1, half - sum[0]);
}
/* -- section: mom -- */
/* Mean of maximum: the mean of the maximal plateaus, else of the distinct maximal points; maximal = at least top x FUZZYC_TOP_SHARE. */
static inline fuzzyc_real fuzzyc_mom_of(fuzzyc_points at, const fuzzyc_real *c, int n, fuzzyc_real fallback) {
    fuzzyc_real top = 0, floor_, total = 0, sum = 0, points = 0, count = 0, u0, u1, f1;
    int i, top0, top1;
    for (i = 0; i < n; ++i) {
        at(c, i, &u1, &f1);
        top = fuzzyc_greater(top, f1);
    }
    if (!(top > 0)) return fallback;
    floor_ = top * FUZZYC_TOP_SHARE;
    at(c, 0, &u0, &f1);
    top0 = f1 >= floor_;
    if (top0) { points = u0; count = 1; }
    for (i = 1; i < n; ++i) {
        at(c, i, &u1, &f1);
        top1 = f1 >= floor_;
        if (top0 && top1) { total += u1 - u0; sum += (u1 - u0) / 2 * (u0 + u1); }
        /* a repeated u counts once; a jump up to the top at a repeated u is new */
        if (top1 && (u1 > u0 || !top0)) { points += u1; count += 1; }
        u0 = u1; top0 = top1;
    }
    return total > 0 ? sum / total : points / count;
}
