/* Hand-written WEDM three-region rule base (Yan & Liao 1998, Table 2) as a plain C baseline for
 * benchmarks/bench_c.py: all 75 rules evaluated on every call.
 * Inputs e1, e2, ce2 in [-1, 1] (clamped); e1 has triangles at -1, 0, 1, the others uniform
 * triangles at -1, -0.5, 0, 0.5, 1 with shoulders at the ends (clamping makes the symmetric
 * triangle formula equal to the shoulder); min, max, center of area over the peaks.
 * Index order NB NS ZO PS PB (e1: N ZO P); HAND_ALL_TABLE[e1][e2][ce2] = {du1, du2}. */
#include <math.h>

static const unsigned char HAND_ALL_TABLE[3][5][5][2] = {{{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 0}, {1, 0}, {1, 0}, {1, 0}}, {{1, 0}, {1, 0}, {1, 0}, {1, 0}, {1, 0}}, {{1, 1}, {2, 1}, {2, 1}, {2, 1}, {2, 1}}},
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 0}, {1, 0}, {1, 0}, {0, 0}}, {{0, 0}, {1, 1}, {2, 1}, {1, 1}, {3, 1}}, {{1, 1}, {2, 2}, {3, 2}, {3, 2}, {3, 2}}, {{1, 1}, {1, 1}, {3, 2}, {3, 2}, {3, 2}}},
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 1}, {1, 1}, {1, 1}, {1, 0}}, {{1, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}, {{3, 1}, {2, 2}, {3, 3}, {4, 3}, {4, 4}}, {{3, 1}, {3, 1}, {4, 4}, {4, 4}, {4, 4}}}};
static const float HAND_ALL_PEAKS[5] = {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f};

static float hand_all_clamp(float x) { return x < -1.0f ? -1.0f : (x > 1.0f ? 1.0f : x); }

static float hand_all_tri(float x, float peak, float half_width) {
    float mu = 1.0f - fabsf(x - peak) / half_width;
    return mu > 0.0f ? mu : 0.0f;
}

void hand_wedm_all_rules(const float x[3], float y[2]) {
    float m1[3], m2[5], m3[5], a1[5] = {0}, a2[5] = {0};
    float e1 = hand_all_clamp(x[0]), e2 = hand_all_clamp(x[1]), ce2 = hand_all_clamp(x[2]);
    float num1 = 0.0f, num2 = 0.0f, den1 = 0.0f, den2 = 0.0f;
    int i, j, k;
    for (i = 0; i < 3; ++i) m1[i] = hand_all_tri(e1, (float)(i - 1), 1.0f);
    for (j = 0; j < 5; ++j) {
        m2[j] = hand_all_tri(e2, HAND_ALL_PEAKS[j], 0.5f);
        m3[j] = hand_all_tri(ce2, HAND_ALL_PEAKS[j], 0.5f);
    }
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 5; ++j)
            for (k = 0; k < 5; ++k) {
                float act = m1[i] < m2[j] ? m1[i] : m2[j];
                const unsigned char *c = HAND_ALL_TABLE[i][j][k];
                act = act < m3[k] ? act : m3[k];
                if (act > a1[c[0]]) a1[c[0]] = act;
                if (act > a2[c[1]]) a2[c[1]] = act;
            }
    for (j = 0; j < 5; ++j) {
        num1 += a1[j] * HAND_ALL_PEAKS[j]; den1 += a1[j];
        num2 += a2[j] * HAND_ALL_PEAKS[j]; den2 += a2[j];
    }
    y[0] = den1 > 0.0f ? num1 / den1 : 0.0f;
    y[1] = den2 > 0.0f ? num2 / den2 : 0.0f;
}
