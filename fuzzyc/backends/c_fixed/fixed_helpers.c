/*
 * The q15/q31 headers' helpers that do not depend on the rule base.  Each header pastes the
 * section below with fuzzyc_fx_ / FUZZYC_FX_ replaced by its own prefixes (NAME_q15_sat,
 * NAME_Q15_ONE, ...; see fuzzyc/backends/c_template.py), so it stays one file and two headers
 * can share a translation unit.  The format enters through two macros the header defines: FUZZYC_FX_ONE
 * (a membership of 1, 2^MF) and FUZZYC_FX_MF (its fraction bits); every helper works on
 * int64_t.  Compiles alone: gcc -std=c99 -DFUZZYC_FX_ONE=32768 -DFUZZYC_FX_MF=15 -c
 */
#include <stdint.h>
/* -- section: helpers -- */
static inline int64_t fuzzyc_fx_sat(int64_t v, int64_t lo, int64_t hi) { return v < lo ? lo : (v > hi ? hi : v); }
/* v / 2**s rounded to nearest (s >= 1; >> of a negative int64 is arithmetic on every compiler fuzzyc supports). */
static inline int64_t fuzzyc_fx_shr(int64_t v, int s) { return (v + ((int64_t)1 << (s - 1))) >> s; }
/* sat(a + b, lo, hi) that never overflows, whatever a holds (b and the bounds are small); the outer sat
   changes nothing, it shows a value analysis (Frama-C EVA) the result's range. */
static inline int64_t fuzzyc_fx_sat_add(int64_t a, int64_t b, int64_t lo, int64_t hi) { return fuzzyc_fx_sat(fuzzyc_fx_sat(a, lo - b, hi - b) + b, lo, hi); }
static inline int64_t fuzzyc_fx_greater(int64_t a, int64_t b) { return a > b ? a : b; }
/* The two active terms of an input at xq and their memberships. */
static inline void fuzzyc_fx_active(int64_t xq, const int64_t *breaks, int nb, const int64_t (*pieces)[6], const unsigned char (*active)[2], int64_t m[2], unsigned char id[2]) {
    int k = 0, b, s;
    const int64_t *q;
    for (b = 0; b < nb; ++b) k += xq >= breaks[b];
    q = pieces[k];
    for (s = 0; s < 2; ++s) {
        const int64_t *piece = q + 3 * s;
        /* rounded to nearest: numerator and width have one sign (truncating would bias every membership low, which an integrator downstream sums) */
        /* |xq - anchor| <= |width| inside the segment, so holding it there changes no membership
           (beyond, mu leaves [0, ONE] and saturates either way) and shows that the product fits in int64 */
        const int64_t w = piece[1] < 0 ? -piece[1] : piece[1];
        const int64_t d = fuzzyc_fx_sat(xq - piece[0], -w, w);
        int64_t mu = w == 0 ? piece[2] : piece[2] + (d * FUZZYC_FX_ONE + piece[1] / 2) / piece[1];
        m[s] = fuzzyc_fx_sat(mu, 0, FUZZYC_FX_ONE);
    }
    id[0] = active[k][0]; id[1] = active[k][1];
}
static inline int64_t fuzzyc_fx_lesser(int64_t a, int64_t b) { return a < b ? a : b; }
static inline int64_t fuzzyc_fx_product(int64_t a, int64_t b) { return fuzzyc_fx_shr(a * b, FUZZYC_FX_MF); }
