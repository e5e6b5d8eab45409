/* Hand-written WEDM three-region rule base (Yan & Liao 1998, Table 2) as a plain C baseline for
 * benchmarks/bench_c.py: only the at most 2 x 2 x 2 = 8 rules whose input terms are active.
 * Same terms and inference as hand_wedm_all_rules.c: per input the two neighbouring triangles
 * of a uniform partition are found by arithmetic (no search), memberships 1 - f and f.
 * HAND_ACTIVE_TABLE[e1][e2][ce2] = {du1, du2}, index order NB NS ZO PS PB (e1: N ZO P). */
static const unsigned char HAND_ACTIVE_TABLE[3][5][5][2] = {{{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 0}, {1, 0}, {1, 0}, {1, 0}}, {{1, 0}, {1, 0}, {1, 0}, {1, 0}, {1, 0}}, {{1, 1}, {2, 1}, {2, 1}, {2, 1}, {2, 1}}},
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 0}, {1, 0}, {1, 0}, {0, 0}}, {{0, 0}, {1, 1}, {2, 1}, {1, 1}, {3, 1}}, {{1, 1}, {2, 2}, {3, 2}, {3, 2}, {3, 2}}, {{1, 1}, {1, 1}, {3, 2}, {3, 2}, {3, 2}}},
 {{{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}}, {{0, 0}, {1, 1}, {1, 1}, {1, 1}, {1, 0}}, {{1, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}, {{3, 1}, {2, 2}, {3, 3}, {4, 3}, {4, 4}}, {{3, 1}, {3, 1}, {4, 4}, {4, 4}, {4, 4}}}};
static const float HAND_ACTIVE_PEAKS[5] = {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f};

/* x in [-1, 1] over n uniform terms: the left term index and the right term's membership. */
static int hand_active_cell(float x, int n, float *frac) {
    float pos = ((x < -1.0f ? -1.0f : (x > 1.0f ? 1.0f : x)) + 1.0f) * (float)(n - 1) * 0.5f;
    int left = (int)pos;
    if (left > n - 2) left = n - 2;
    *frac = pos - (float)left;
    return left;
}

void hand_wedm_active_rules(const float x[3], float y[2]) {
    float f1, f2, f3, a1[5] = {0}, a2[5] = {0};
    float num1 = 0.0f, num2 = 0.0f, den1 = 0.0f, den2 = 0.0f;
    int i0 = hand_active_cell(x[0], 3, &f1), j0 = hand_active_cell(x[1], 5, &f2);
    int k0 = hand_active_cell(x[2], 5, &f3), c, t;
    for (c = 0; c < 8; ++c) {
        int di = c >> 2, dj = (c >> 1) & 1, dk = c & 1;
        float m1 = di ? f1 : 1.0f - f1, m2 = dj ? f2 : 1.0f - f2, m3 = dk ? f3 : 1.0f - f3;
        float act = m1 < m2 ? m1 : m2;
        const unsigned char *cons = HAND_ACTIVE_TABLE[i0 + di][j0 + dj][k0 + dk];
        act = act < m3 ? act : m3;
        if (act > a1[cons[0]]) a1[cons[0]] = act;
        if (act > a2[cons[1]]) a2[cons[1]] = act;
    }
    for (t = 0; t < 5; ++t) {
        num1 += a1[t] * HAND_ACTIVE_PEAKS[t]; den1 += a1[t];
        num2 += a2[t] * HAND_ACTIVE_PEAKS[t]; den2 += a2[t];
    }
    y[0] = den1 > 0.0f ? num1 / den1 : 0.0f;
    y[1] = den2 > 0.0f ? num2 / den2 : 0.0f;
}
