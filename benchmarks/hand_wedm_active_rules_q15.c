/* Hand-written WEDM three-region rule base (Yan & Liao 1998, Table 2) in 16-bit fixed point, the
 * q15 counterpart of hand_wedm_active_rules.c for benchmarks/bench_c.py and run_all.py: written
 * from the paper's table (../shared/REFERENCE.md section 1) and the rule base file's break points
 * (uniform isosceles partitions of [-1, 1]: peaks -1, 0, 1 for e1; -1, -0.5, 0, 0.5, 1 for e2,
 * ce2, du1, du2), not from the generator's output.  Max-min inference, center of area over the
 * output terms' peaks (eq. 2); only the at most 2 x 2 x 2 = 8 rules whose input terms are active.
 *
 * Fixed point: an input is 0..32767 for -1..1 (the interface of the generated q15 header's
 * rule base, so the benchmark's float-to-q15 conversion is the same for both); a membership is
 * 0..32767 for 0..1; an output is -32767..32767 for -1..1 (rounded to nearest), 0 when no rule
 * fires.  Table and order of terms as in hand_wedm_active_rules.c: [e1][e2][ce2] = {du1, du2},
 * index order NB NS ZO PS PB (e1: N ZO P). */
#include <stdint.h>

#define HQ_ONE 32767

static const unsigned char HAND_Q15_TABLE[3][5][5][2] = {
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}},
  {{0, 0}, {1, 0}, {1, 0}, {1, 0}, {1, 0}}, {{1, 0}, {1, 0}, {1, 0}, {1, 0}, {1, 0}},
  {{1, 1}, {2, 1}, {2, 1}, {2, 1}, {2, 1}}},
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 0}, {1, 0}, {1, 0}, {0, 0}},
  {{0, 0}, {1, 1}, {2, 1}, {1, 1}, {3, 1}}, {{1, 1}, {2, 2}, {3, 2}, {3, 2}, {3, 2}},
  {{1, 1}, {1, 1}, {3, 2}, {3, 2}, {3, 2}}},
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 1}, {1, 1}, {1, 1}, {1, 0}},
  {{1, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}, {{3, 1}, {2, 2}, {3, 3}, {4, 3}, {4, 4}},
  {{3, 1}, {3, 1}, {4, 4}, {4, 4}, {4, 4}}}};

/* x in 0..32767 over n uniform terms: the left term's index; *right the right term's
 * membership (the left term's is HQ_ONE - *right). */
static int hand_q15_cell(int16_t x, int n, int32_t *right) {
    int32_t clipped = x < 0 ? 0 : x;
    int32_t pos = clipped * (n - 1);              /* in 1/32767ths of a term spacing */
    int left = pos / HQ_ONE;
    if (left > n - 2) left = n - 2;
    *right = pos - left * HQ_ONE;
    return left;
}

/* sum(a[t] * peak[t]) / sum(a[t]) with the peaks -1, -0.5, 0, 0.5, 1: in halves, t - 2.
 * 32-bit throughout: |a[4] - a[0]| and |a[3] - a[1]| are at most 32767, so |num| <= 98301 and
 * |num| * 16383 + den / 2 < 2^31; |num| <= 2 den, so |result| <= 32767. */
static int16_t hand_q15_coa(const int32_t a[5]) {
    int32_t num = 2 * (a[4] - a[0]) + (a[3] - a[1]);
    int32_t den = a[0] + a[1] + a[2] + a[3] + a[4];
    if (den == 0) return 0;
    return (int16_t)((num * (HQ_ONE / 2) + (num >= 0 ? den / 2 : -(den / 2))) / den);
}

void hand_wedm_active_rules_q15(const int16_t x[3], int16_t y[2]) {
    int32_t f1, f2, f3, a1[5] = {0}, a2[5] = {0};
    int i0 = hand_q15_cell(x[0], 3, &f1), j0 = hand_q15_cell(x[1], 5, &f2);
    int k0 = hand_q15_cell(x[2], 5, &f3), c;
    for (c = 0; c < 8; ++c) {
        int di = c >> 2, dj = (c >> 1) & 1, dk = c & 1;
        int32_t m1 = di ? f1 : HQ_ONE - f1, m2 = dj ? f2 : HQ_ONE - f2;
        int32_t m3 = dk ? f3 : HQ_ONE - f3;
        int32_t act = m1 < m2 ? m1 : m2;
        const unsigned char *cons = HAND_Q15_TABLE[i0 + di][j0 + dj][k0 + dk];
        act = act < m3 ? act : m3;
        if (act > a1[cons[0]]) a1[cons[0]] = act;
        if (act > a2[cons[1]]) a2[cons[1]] = act;
    }
    y[0] = hand_q15_coa(a1);
    y[1] = hand_q15_coa(a2);
}
