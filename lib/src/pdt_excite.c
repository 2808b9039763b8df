/*
 * pdtfit excitation generators (pdt_excite.h); equations and the PRBS
 * polynomial table are explained in docs/experiments.md.
 */
#include "pdt/pdt_excite.h"

#include "pdt_internal.h"

#define EXCITE_MAGIC PDT_MAGIC('P', 'D', 'E', 'X')

/*
 * Primitive feedback polynomials x^n + ... + 1 over GF(2), one per register
 * length n = 2 .. 31, as the exponents of their non-constant terms (0 pads).
 * The chip sequence obeys a(k) = XOR over these t of a(k - t). Trinomials
 * where one exists, else pentanomials (the widely used table of Xilinx
 * application note XAPP052); each was checked primitive by testing
 * x^(2^n - 1) = 1 and x^((2^n - 1) / q) != 1 for every prime factor q.
 */
static const uint8_t prbs_taps[30][4] = {
    {2, 1, 0, 0},   {3, 2, 0, 0},   {4, 3, 0, 0},     {5, 3, 0, 0},   {6, 5, 0, 0},
    {7, 6, 0, 0},   {8, 6, 5, 4},   {9, 5, 0, 0},     {10, 7, 0, 0},  {11, 9, 0, 0},
    {12, 6, 4, 1},  {13, 4, 3, 1},  {14, 5, 3, 1},    {15, 14, 0, 0}, {16, 15, 13, 4},
    {17, 14, 0, 0}, {18, 11, 0, 0}, {19, 6, 2, 1},    {20, 17, 0, 0}, {21, 19, 0, 0},
    {22, 21, 0, 0}, {23, 18, 0, 0}, {24, 23, 22, 17}, {25, 22, 0, 0}, {26, 6, 2, 1},
    {27, 5, 2, 1},  {28, 25, 0, 0}, {29, 27, 0, 0},   {30, 6, 4, 1},  {31, 28, 0, 0},
};

void pdt_excite_config_default(pdt_excite_config_t *cfg, pdt_excite_kind_t kind)
{
    if (cfg == NULL) {
        return;
    }
    cfg->kind = kind;
    cfg->Ts = PDT_R(0.0);
    cfg->u0 = PDT_R(0.0);
    cfg->u_min = -PDT_REAL_MAX;
    cfg->u_max = PDT_REAL_MAX;
    cfg->clamp = false;
    cfg->pre = PDT_R(0.0);
    cfg->amplitude = PDT_R(1.0);
    cfg->duration = PDT_R(0.0);
    cfg->t_on = PDT_R(1.0);
    cfg->t_off = PDT_R(1.0);
    cfg->count = 1u;
    cfg->f0 = PDT_R(0.0);
    cfg->f1 = PDT_R(0.0);
    cfg->prbs_bits = 7u;
    cfg->prbs_hold = 1u;
    cfg->prbs_seed = 1u;
    cfg->periods = 1u;
    cfg->setpoint = PDT_R(0.0);
    cfg->d = PDT_R(1.0);
    cfg->bias = PDT_R(0.0);
    cfg->eps = PDT_R(0.0);
    cfg->action = PDT_EXCITE_REVERSE;
    cfg->relay_skip = 0u;
    cfg->relay_cycles = 3u;
    cfg->relay_settle = PDT_R(0.1);
}

static pdt_real_t clamp_to(pdt_real_t x, pdt_real_t lo, pdt_real_t hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* Whole samples nearest to t seconds; false when beyond the counters. */
static bool to_samples(pdt_real_t t, pdt_real_t Ts, uint32_t *n)
{
    pdt_real_t x = t / Ts + PDT_R(0.5);
    if (!(x < (pdt_real_t)PDT_EXCITE_MAX_SAMPLES)) {
        return false;
    }
    *n = (uint32_t)pdt_floor(x);
    return true;
}

static bool all_finite(const pdt_real_t *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (!pdt_finite(v[i])) {
            return false;
        }
    }
    return true;
}

/* The value checks of init that give PDT_ERR_ARG. */
static bool config_valid(const pdt_excite_config_t *c)
{
    const pdt_real_t common[] = {c->Ts, c->u0, c->u_min, c->u_max, c->pre};
    if (!all_finite(common, sizeof common / sizeof common[0]) || !(c->Ts > PDT_R(0.0)) ||
        c->pre < PDT_R(0.0)) {
        return false;
    }
    switch (c->kind) {
    case PDT_EXCITE_STEP:
        return pdt_finite(c->amplitude) && c->amplitude != PDT_R(0.0) && pdt_finite(c->duration) &&
               c->duration >= PDT_R(0.0);
    case PDT_EXCITE_PULSE:
        return pdt_finite(c->amplitude) && c->amplitude != PDT_R(0.0) && pdt_finite(c->t_on) &&
               pdt_finite(c->t_off) && c->t_off >= PDT_R(0.0) && c->t_on / c->Ts >= PDT_R(0.5);
    case PDT_EXCITE_CHIRP: {
        pdt_real_t nyq = PDT_R(0.5) / c->Ts;
        return pdt_finite(c->amplitude) && c->amplitude > PDT_R(0.0) && pdt_finite(c->duration) &&
               c->duration / c->Ts >= PDT_R(0.5) && pdt_finite(c->f0) && pdt_finite(c->f1) &&
               c->f0 >= PDT_R(0.0) && c->f1 >= PDT_R(0.0) && c->f0 <= nyq && c->f1 <= nyq;
    }
    case PDT_EXCITE_PRBS:
        return pdt_finite(c->amplitude) && c->amplitude > PDT_R(0.0) && c->prbs_bits >= 2u &&
               c->prbs_bits <= 31u && c->prbs_hold >= 1u &&
               (c->prbs_seed & (((uint32_t)1u << c->prbs_bits) - 1u)) != 0u;
    case PDT_EXCITE_RELAY:
        return pdt_finite(c->setpoint) && pdt_finite(c->d) && c->d > PDT_R(0.0) &&
               pdt_finite(c->bias) && pdt_finite(c->eps) && c->eps >= PDT_R(0.0) &&
               (c->action == PDT_EXCITE_REVERSE || c->action == PDT_EXCITE_DIRECT) &&
               c->relay_cycles >= 1u && c->relay_cycles <= PDT_EXCITE_RELAY_MAX_CYCLES &&
               pdt_finite(c->relay_settle) && c->relay_settle >= PDT_R(0.0) &&
               c->relay_settle < PDT_R(1.0);
    default:
        return false;
    }
}

/* Register bit i holds chip a(j + i); the next chip a(j + n) is the XOR of
 * a(j + n - t) over the taps t, i.e. of register bits n - t. */
static uint32_t prbs_mask(uint32_t n)
{
    uint32_t mask = 0u;
    for (unsigned i = 0; i < 4u; i++) {
        uint32_t t = prbs_taps[n - 2u][i];
        if (t != 0u) {
            mask |= (uint32_t)1u << (n - t);
        }
    }
    return mask;
}

static uint32_t parity(uint32_t x)
{
    x ^= x >> 16;
    x ^= x >> 8;
    x ^= x >> 4;
    x ^= x >> 2;
    x ^= x >> 1;
    return x & 1u;
}

/* A generator at its start: every counter and memory 0. */
static void excite_clear(pdt_excite_t *g)
{
    g->done = false;
    g->k = 0u;
    g->n_on = 0u;
    g->n_off = 0u;
    g->pos = 0u;
    g->c1 = PDT_R(0.0);
    g->c2 = PDT_R(0.0);
    g->lfsr = 0u;
    g->taps = 0u;
    g->started = false;
    g->high = false;
    g->rose = false;
    g->since_rise = 0u;
    g->fall_at = 0u;
    g->seen = 0u;
    g->stored = 0u;
    g->pv_max = PDT_R(0.0);
    g->pv_min = PDT_R(0.0);
    for (unsigned i = 0; i < PDT_EXCITE_RELAY_MAX_CYCLES; i++) {
        g->per[i] = 0u;
        g->amp[i] = PDT_R(0.0);
    }
}

/* The kind's part of the set-up: its samples after pre in *body (0: no
 * end), its state, and its two output levels. False when a length does
 * not fit. Lengths are in 64 bits so that the sum of parts cannot wrap. */
static bool excite_kind(const pdt_excite_config_t *cfg, pdt_excite_t *g, uint64_t *body,
                        pdt_real_t *up, pdt_real_t *down)
{
    uint32_t n;
    *body = 0u;
    *up = cfg->u0 + cfg->amplitude;
    *down = cfg->u0;
    switch (cfg->kind) {
    case PDT_EXCITE_STEP:
        if (!to_samples(cfg->duration, cfg->Ts, &n)) {
            return false;
        }
        /* A duration under half a sample would end before starting: take
         * it as one sample rather than as "no end". */
        *body = (cfg->duration > PDT_R(0.0) && n == 0u) ? 1u : n;
        break;
    case PDT_EXCITE_PULSE:
        if (!to_samples(cfg->t_on, cfg->Ts, &g->n_on) ||
            !to_samples(cfg->t_off, cfg->Ts, &g->n_off)) {
            return false;
        }
        *body = (uint64_t)cfg->count * ((uint64_t)g->n_on + g->n_off);
        break;
    case PDT_EXCITE_CHIRP:
        if (!to_samples(cfg->duration, cfg->Ts, &n)) {
            return false;
        }
        *body = n;
        g->c1 = cfg->f0 * cfg->Ts;
        g->c2 = (cfg->f1 - cfg->f0) * cfg->Ts / (PDT_R(2.0) * (pdt_real_t)n);
        *down = cfg->u0 - cfg->amplitude;
        break;
    case PDT_EXCITE_PRBS:
        *body = (uint64_t)cfg->periods * (((uint64_t)1u << cfg->prbs_bits) - 1u) * cfg->prbs_hold;
        g->lfsr = cfg->prbs_seed & (((uint32_t)1u << cfg->prbs_bits) - 1u);
        g->taps = prbs_mask(cfg->prbs_bits);
        *down = cfg->u0 - cfg->amplitude;
        break;
    default: /* RELAY */
        *up = cfg->u0 + cfg->bias + cfg->d;
        *down = cfg->u0 + cfg->bias - cfg->d;
        break;
    }
    return true;
}

/* The output levels up and down within the limits into g (clamped if the
 * configuration allows it), or PDT_ERR_OUTPUT_LIMIT. */
static pdt_status_t excite_levels(const pdt_excite_config_t *cfg, pdt_real_t up, pdt_real_t down,
                                  pdt_excite_t *g)
{
    if (cfg->u0 < cfg->u_min || cfg->u0 > cfg->u_max) {
        return PDT_ERR_OUTPUT_LIMIT;
    }
    if (!pdt_finite(up) || !pdt_finite(down)) {
        return PDT_ERR_OUTPUT_LIMIT;
    }
    bool inside = up >= cfg->u_min && up <= cfg->u_max && down >= cfg->u_min && down <= cfg->u_max;
    if (!inside && !cfg->clamp) {
        return PDT_ERR_OUTPUT_LIMIT;
    }
    g->hi = clamp_to(up, cfg->u_min, cfg->u_max);
    g->lo = clamp_to(down, cfg->u_min, cfg->u_max);
    if (g->hi == g->lo) {
        return PDT_ERR_OUTPUT_LIMIT;
    }
    return PDT_OK;
}

pdt_status_t pdt_excite_init(pdt_excite_t *gen, const pdt_excite_config_t *cfg)
{
    if (gen == NULL || cfg == NULL || !config_valid(cfg)) {
        return PDT_ERR_ARG;
    }
    if (cfg->u_min > cfg->u_max) {
        return PDT_ERR_BOUNDS;
    }

    pdt_excite_t g;
    g.cfg = *cfg;
    g.magic = EXCITE_MAGIC;
    excite_clear(&g);
    uint64_t body;
    pdt_real_t up;
    pdt_real_t down;
    if (!to_samples(cfg->pre, cfg->Ts, &g.n_pre)) {
        return PDT_ERR_LENGTH;
    }
    if (!excite_kind(cfg, &g, &body, &up, &down)) {
        return PDT_ERR_LENGTH;
    }
    uint64_t total = body == 0u ? 0u : (uint64_t)g.n_pre + body;
    if (total > PDT_EXCITE_MAX_SAMPLES) {
        return PDT_ERR_LENGTH;
    }
    g.n_total = (uint32_t)total;
    pdt_status_t st = excite_levels(cfg, up, down, &g);
    if (st != PDT_OK) {
        return st;
    }
    *gen = g;
    return PDT_OK;
}

/* Whether the cycle that ends now is the limit cycle: from rest, the first
 * cycles of a relay are lopsided (one half longer, the peaks off-centre);
 * the limit cycle of a relay without bias is symmetric. */
static bool relay_settled(const pdt_excite_t *g)
{
    const pdt_excite_config_t *c = &g->cfg;
    if (!(c->relay_settle > PDT_R(0.0)) || c->bias != PDT_R(0.0)) {
        return false;
    }
    pdt_real_t per = (pdt_real_t)g->since_rise;
    pdt_real_t halves = pdt_fabs(PDT_R(2.0) * (pdt_real_t)g->fall_at - per);
    pdt_real_t pp = g->pv_max - g->pv_min;
    pdt_real_t off = pdt_fabs((g->pv_max - c->setpoint) - (c->setpoint - g->pv_min));
    return halves <= c->relay_settle * per && off <= c->relay_settle * pp;
}

/* One relay sample; returns true when the relay has measured its cycles. */
static bool relay_step(pdt_excite_t *g, pdt_real_t pv)
{
    const pdt_excite_config_t *c = &g->cfg;
    pdt_real_t e = c->action == PDT_EXCITE_REVERSE ? c->setpoint - pv : pv - c->setpoint;
    bool rising = false;
    if (!g->started) {
        g->started = true;
        g->high = e >= PDT_R(0.0);
    } else if (g->high && e < -c->eps) {
        g->high = false;
        g->fall_at = g->since_rise;
    } else if (!g->high && e > c->eps) {
        g->high = true;
        rising = true;
    }
    if (rising) {
        if (g->rose) {
            g->seen++;
            if (g->seen > c->relay_skip) {
                /* The relay ends when the array is full, so the cycles kept
                 * are always the last ones. */
                g->per[g->stored] = g->since_rise;
                g->amp[g->stored] = PDT_R(0.5) * (g->pv_max - g->pv_min);
                g->stored++;
                if (g->stored == c->relay_cycles) {
                    return true;
                }
                if (relay_settled(g)) {
                    g->per[0] = g->per[g->stored - 1u];
                    g->amp[0] = g->amp[g->stored - 1u];
                    g->stored = 1u;
                    return true;
                }
            }
        }
        g->rose = true;
        g->since_rise = 0u;
        g->pv_max = pv;
        g->pv_min = pv;
    } else if (g->rose) {
        g->pv_max = pv > g->pv_max ? pv : g->pv_max;
        g->pv_min = pv < g->pv_min ? pv : g->pv_min;
    }
    if (g->since_rise != UINT32_MAX) {
        g->since_rise++;
    }
    return false;
}

pdt_status_t pdt_excite_next(pdt_excite_t *gen, pdt_real_t pv, pdt_real_t *u)
{
    if (gen == NULL || u == NULL) {
        return PDT_ERR_ARG;
    }
    if (gen->magic != EXCITE_MAGIC) {
        return PDT_ERR_STATE;
    }
    const pdt_excite_config_t *c = &gen->cfg;
    if (!gen->done && gen->n_total != 0u && gen->k >= gen->n_total) {
        gen->done = true;
    }
    if (gen->done) {
        *u = c->u0;
        return PDT_OK;
    }
    if (c->kind == PDT_EXCITE_RELAY && !pdt_finite(pv)) {
        return PDT_ERR_NONFINITE;
    }

    pdt_real_t out = c->u0;
    if (gen->k >= gen->n_pre) {
        switch (c->kind) {
        case PDT_EXCITE_STEP:
            out = gen->hi;
            break;
        case PDT_EXCITE_PULSE:
            out = gen->pos < gen->n_on ? gen->hi : c->u0;
            gen->pos = gen->pos + 1u == gen->n_on + gen->n_off ? 0u : gen->pos + 1u;
            break;
        case PDT_EXCITE_CHIRP: {
            pdt_real_t j = (pdt_real_t)(gen->k - gen->n_pre);
            pdt_real_t cycles = j * (gen->c1 + gen->c2 * j);
            /* sin of the fraction of a cycle only: the whole cycles carry
             * no information and would cost float precision in sin. */
            pdt_real_t frac = cycles - pdt_floor(cycles);
            out = clamp_to(c->u0 + c->amplitude * pdt_sin(PDT_R(2.0) * PDT_PI * frac), c->u_min,
                           c->u_max);
            break;
        }
        case PDT_EXCITE_PRBS:
            out = (gen->lfsr & 1u) != 0u ? gen->hi : gen->lo;
            gen->pos++;
            if (gen->pos == c->prbs_hold) {
                gen->pos = 0u;
                uint32_t fb = parity(gen->lfsr & gen->taps);
                gen->lfsr = (gen->lfsr >> 1) | (fb << (c->prbs_bits - 1u));
            }
            break;
        default: /* RELAY */
            if (relay_step(gen, pv)) {
                gen->done = true;
                *u = c->u0;
                return PDT_OK;
            }
            out = gen->high ? gen->hi : gen->lo;
            break;
        }
    }
    if (gen->k != UINT32_MAX) {
        gen->k++;
    }
    *u = out;
    return PDT_RUNNING;
}

uint32_t pdt_excite_length(const pdt_excite_t *gen)
{
    if (gen == NULL || gen->magic != EXCITE_MAGIC) {
        return 0u;
    }
    return gen->n_total;
}

pdt_status_t pdt_excite_relay_result(const pdt_excite_t *gen, pdt_excite_relay_t *out)
{
    if (gen == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (gen->magic != EXCITE_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (gen->cfg.kind != PDT_EXCITE_RELAY) {
        return PDT_ERR_ARG;
    }
    if (gen->stored == 0u) {
        return PDT_ERR_STATE;
    }
    pdt_real_t per = PDT_R(0.0);
    pdt_real_t amp = PDT_R(0.0);
    for (uint32_t i = 0; i < gen->stored; i++) {
        per += (pdt_real_t)gen->per[i];
        amp += gen->amp[i];
    }
    per /= (pdt_real_t)gen->stored;
    amp /= (pdt_real_t)gen->stored;
    pdt_real_t d = PDT_R(0.5) * (gen->hi - gen->lo);
    out->Ku = PDT_R(4.0) * d / (PDT_PI * amp);
    out->Pu = per * gen->cfg.Ts;
    out->a = amp;
    out->d = d;
    out->cycles = gen->stored;
    return PDT_OK;
}
