/*
 * Instruction-count program of the evaluation kernel
 * (tools/bench/count_instructions.py): the identification's evaluation,
 * pdt_cost_profile of a unit-gain shape on the simulation criterion over
 * the whole record with the offset estimated, as the search calls it.
 * Built for the host (callgrind counts each case function inclusively) and
 * for the Cortex-M4F (QEMU -icount: the port's ticks are 40 instructions
 * each). Only the port surface, so the same source runs on both.
 *
 * Cases, each KB_REPS evaluations of a candidate near the optimum:
 *   *_hint   with the best fit so far as the reference (what the search
 *            does, pdt_cost_profile_hint);
 *   *_cold   without (pdt_cost_profile);
 *   *_many4  four a call (pdt_cost_profile_many);
 *   *_shift4 the optimum's shape at KB_REPS whole-sample dead times from
 *            its response, four a call (what the dead-time profile does).
 * Built with -DKB_BASELINE against a library without
 * pdt_cost_profile_hint, the hint cases call pdt_cost_profile too.
 */
#include <stdint.h>

#include "pdt/pdt.h"
#ifndef KB_BASELINE /* the baseline predates the engine's private header */
#include "pdt_cost_engine.h"
#endif
#include "pdt_port.h"
#include "sim_rng.h"

#ifndef KB_N
#define KB_N 2000u
#endif
#ifndef KB_REPS
#define KB_REPS 20u
#endif

static pdt_real_t g_u[KB_N];
static pdt_real_t g_y[KB_N];
static pdt_real_t g_scratch[KB_N];
static pdt_real_t g_work[PDT_COST_WORKSPACE_SIZE(KB_N) / sizeof(pdt_real_t)];
static pdt_cost_t g_cost;

/* A relay-like record of a FOPDT (K 1.5, tau 20 s, Td 5.5 s, Ts 1 s)
 * around u 2, y 7, with about 25 dB of deterministic output noise. */
static void make_record(void)
{
    const pdt_real_t a = (pdt_real_t)0.951229424500714; /* exp(-1/20) */
    sim_rng64_t r = sim_rng64_seed(2463534242u);
    pdt_real_t x = 0, x1 = 0;
    for (size_t k = 0; k < KB_N; k++) {
        g_u[k] = (pdt_real_t)(((k / 61u) + (k / 97u)) % 2u == 0u ? 2.0 : 3.0);
    }
    for (size_t k = 0; k < KB_N; k++) {
        /* half a sample of the dead time as an average of two taps */
        pdt_real_t u1 = (k >= 6u) ? g_u[k - 6u] - (pdt_real_t)2.0 : 0;
        pdt_real_t u2 = (k >= 7u) ? g_u[k - 7u] - (pdt_real_t)2.0 : 0;
        x = a * x + (pdt_real_t)1.5 * (1 - a) * (pdt_real_t)0.5 * (u1 + u2);
        x1 = (pdt_real_t)(0.08 * (sim_rng64_uniform(&r) - 0.5));
        g_y[k] = (pdt_real_t)7.0 + x + x1;
    }
}

static int prepare(void)
{
    pdt_cost_config_t cc;
    pdt_cost_config_default(&cc);
    cc.Ts = 1;
    cc.u0 = g_u[0];
    cc.y0 = 7;
    cc.delay_max = 100u;
    cc.kind = PDT_COST_SIMULATION;
    cc.whole_record = true;
    cc.use_frequency = false;
    return pdt_cost_init(&g_cost, &cc, g_u, g_y, KB_N, g_work, sizeof g_work) == PDT_OK;
}

static pdt_model_t shape(int sopdt, pdt_real_t detune)
{
    pdt_model_t m;
    if (sopdt) {
        m.kind = PDT_MODEL_SOPDT;
        m.p.sopdt.k = 1;
        m.p.sopdt.a = (pdt_real_t)0.3 * detune; /* 1/(s^2 + 0.3 s + 0.02) */
        m.p.sopdt.b = (pdt_real_t)0.02;
        m.p.sopdt.Td = (pdt_real_t)4.3;
    } else {
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt.K = 1;
        m.p.fopdt.tau = (pdt_real_t)20.0 * detune;
        m.p.fopdt.Td = (pdt_real_t)5.5;
    }
    return m;
}

static pdt_real_t g_sink;
static pdt_real_t g_hint[2][2]; /* gain, offset of the optimum's shape, by model */

static void set_hint(int sopdt)
{
    pdt_model_t best = shape(sopdt, 1);
    pdt_cost_profile_t p;
    if (pdt_cost_profile(&g_cost, &best, 0, 0, g_scratch, &p) == PDT_OK) {
        g_hint[sopdt][0] = p.gain;
        g_hint[sopdt][1] = p.offset;
    }
}

/* KB_REPS evaluations of candidates around the optimum, the reference fit
 * that of the optimum's shape. */
static void run(int sopdt, int hint)
{
    pdt_cost_profile_t p;
#ifndef KB_BASELINE
    const pdt_cost_hint_t h = {g_hint[sopdt][0], g_hint[sopdt][1], 0};
#endif
    for (unsigned i = 0; i < KB_REPS; i++) {
        pdt_model_t m = shape(sopdt, (pdt_real_t)(1.0 + 0.004 * (double)(i % 5u)));
#ifdef KB_BASELINE
        (void)hint;
        (void)pdt_cost_profile(&g_cost, &m, 0, 0, g_scratch, &p);
#else
        (void)pdt_cost_profile_hint(&g_cost, &m, 0, 0, hint ? &h : NULL, g_scratch, &p);
#endif
        g_sink += p.cost;
    }
}

/* The same candidates four at a time (pdt_cost_profile_many). */
static void run_many(int sopdt)
{
    pdt_cost_profile_t p[4];
    pdt_model_t m[4];
    const pdt_real_t lo[4] = {0, 0, 0, 0}, hi[4] = {0, 0, 0, 0};
    for (unsigned i = 0; i < KB_REPS; i += 4u) {
        for (unsigned k = 0; k < 4u; k++) {
            m[k] = shape(sopdt, (pdt_real_t)(1.0 + 0.004 * (double)((i + k) % 5u)));
        }
#ifdef KB_BASELINE
        (void)lo;
        (void)hi;
        for (unsigned k = 0; k < 4u; k++) {
            (void)pdt_cost_profile(&g_cost, &m[k], 0, 0, g_scratch, &p[k]);
        }
#else
        const pdt_cost_hint_t h = {g_hint[sopdt][0], g_hint[sopdt][1], 0};
        (void)pdt_cost_profile_many(&g_cost, m, 4u, lo, hi, &h, g_scratch, p);
#endif
        g_sink += p[0].cost + p[1].cost + p[2].cost + p[3].cost;
    }
}

/* Twenty whole-sample dead times (2 .. 21 s) of the optimum's shape, as
 * the identification's dead-time profile scores them: the shape's
 * response once (pdt_cost_response), then four dead times a call from it
 * (pdt_cost_profile_shift); the baseline evaluates each. */
static void run_shift(int sopdt)
{
    pdt_cost_profile_t p[4];
    const pdt_model_t m = shape(sopdt, 1);
#ifdef KB_BASELINE
    for (unsigned i = 0; i < KB_REPS; i++) {
        pdt_model_t at = m;
        if (sopdt) {
            at.p.sopdt.Td = (pdt_real_t)(2u + i);
        } else {
            at.p.fopdt.Td = (pdt_real_t)(2u + i);
        }
        (void)pdt_cost_profile(&g_cost, &at, 0, 0, g_scratch, &p[0]);
        g_sink += p[0].cost;
    }
#else
    const pdt_cost_hint_t h = {g_hint[sopdt][0], g_hint[sopdt][1], 0};
    (void)pdt_cost_response(&g_cost, &m, g_scratch);
    for (unsigned i = 0; i < KB_REPS; i += 4u) {
        const size_t delay[4] = {2u + i, 3u + i, 4u + i, 5u + i};
        (void)pdt_cost_profile_shift(&g_cost, &m, g_scratch, delay, 4u, 0, 0, &h, p);
        g_sink += p[0].cost + p[1].cost + p[2].cost + p[3].cost;
    }
#endif
}

/* One function per case, called through pointers so that the host
 * compiler keeps each one for callgrind's inclusive count. */
void kb_fopdt_hint(void);
void kb_fopdt_cold(void);
void kb_sopdt_hint(void);
void kb_sopdt_cold(void);
void kb_fopdt_many4(void);
void kb_sopdt_many4(void);
void kb_fopdt_shift4(void);
void kb_sopdt_shift4(void);
void kb_fopdt_hint(void)
{
    run(0, 1);
}
void kb_fopdt_cold(void)
{
    run(0, 0);
}
void kb_sopdt_hint(void)
{
    run(1, 1);
}
void kb_sopdt_cold(void)
{
    run(1, 0);
}
void kb_fopdt_many4(void)
{
    run_many(0);
}
void kb_sopdt_many4(void)
{
    run_many(1);
}
void kb_fopdt_shift4(void)
{
    run_shift(0);
}
void kb_sopdt_shift4(void)
{
    run_shift(1);
}

static void put(const char *s)
{
    size_t n = 0;
    while (s[n] != '\0') {
        n++;
    }
    pdt_port_write(s, n);
}

static void put_u64(uint64_t v)
{
    char b[24];
    size_t i = sizeof b - 1u;
    b[i] = '\0';
    do {
        b[--i] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    put(&b[i]);
}

int main(void)
{
    static void (*volatile const cases[])(void) = {kb_fopdt_hint,   kb_fopdt_cold,  kb_sopdt_hint,
                                                   kb_sopdt_cold,   kb_fopdt_many4, kb_sopdt_many4,
                                                   kb_fopdt_shift4, kb_sopdt_shift4};
    static const char *const names[] = {"kb_fopdt_hint",   "kb_fopdt_cold",  "kb_sopdt_hint",
                                        "kb_sopdt_cold",   "kb_fopdt_many4", "kb_sopdt_many4",
                                        "kb_fopdt_shift4", "kb_sopdt_shift4"};
    pdt_port_init();
    make_record();
    if (!prepare()) {
        put("FAIL cost init\n");
        pdt_port_exit(1);
    }
    set_hint(0);
    set_hint(1);
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        uint64_t t0 = pdt_port_ticks();
        cases[i]();
        uint64_t t1 = pdt_port_ticks();
        put("case ");
        put(names[i]);
        put(" n ");
        put_u64(KB_N);
        put(" evaluations ");
        put_u64(KB_REPS);
        put(" ticks ");
        put_u64(t1 - t0);
        put("\n");
    }
    pdt_port_exit(0);
    return 0;
}
