/*
 * pdtfit models: first- and second-order plus dead time, their forms,
 * conversions, step responses and frequency responses.
 *
 * Units: time in seconds, frequency in rad/s, phase in radians. Gains are in
 * the caller's engineering units (output unit per input unit).
 *
 * The SOPDT is held in the paper's form (2), K e^{-Td s} / (s^2 + a s + b),
 * because that form alone covers every case pdtfit needs — overdamped,
 * critically damped, underdamped and, with b = 0, the integrator with a lag —
 * without a special value. The other forms are conversions.
 */
#ifndef PDT_MODEL_H
#define PDT_MODEL_H

#include "pdt/pdt_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* FOPDT, paper (1): G(s) = K e^{-Td s} / (tau s + 1). Valid when K, tau and
 * Td are finite, tau > 0 and Td >= 0. */
typedef struct pdt_model_fopdt {
    pdt_real_t K;   /* DC gain, output units per input unit */
    pdt_real_t tau; /* time constant, s */
    pdt_real_t Td;  /* dead time, s */
} pdt_model_fopdt_t;

/* SOPDT, paper (2): G(s) = k e^{-Td s} / (s^2 + a s + b). Valid when all are
 * finite, a > 0, b >= 0 and Td >= 0. The DC gain is k / b; b = 0 is the
 * integrator with a lag, (k / a) e^{-Td s} / (s (s / a + 1)). */
typedef struct pdt_model_sopdt {
    pdt_real_t k;  /* numerator gain, output units per input unit per s^2 */
    pdt_real_t a;  /* 1/s */
    pdt_real_t b;  /* 1/s^2 */
    pdt_real_t Td; /* dead time, s */
} pdt_model_sopdt_t;

/* SOPDT by DC gain, natural frequency and damping:
 * K wn^2 e^{-Td s} / (s^2 + 2 zeta wn s + wn^2). Valid for wn > 0, zeta > 0.
 * Does not exist for the integrating case (b = 0). */
typedef struct pdt_model_natural {
    pdt_real_t K;    /* DC gain */
    pdt_real_t wn;   /* natural frequency, rad/s */
    pdt_real_t zeta; /* damping ratio, dimensionless */
    pdt_real_t Td;   /* dead time, s */
} pdt_model_natural_t;

/* SOPDT in time-constant form, paper (13): K e^{-Td s} / ((T1 s + 1)(T2 s + 1)).
 * For a real pair, T1 >= T2 > 0 are the time constants. For a complex-
 * conjugate pair (complex = true) the time constants are re +/- j im, with
 * re > 0 and im > 0, so the denominator is (re^2 + im^2) s^2 + 2 re s + 1. */
typedef struct pdt_model_tc {
    pdt_real_t K;  /* DC gain */
    pdt_real_t T1; /* real pair: larger time constant, s; complex: re, s */
    pdt_real_t T2; /* real pair: smaller time constant, s; complex: im, s */
    bool complex;  /* true for a complex-conjugate pair */
    pdt_real_t Td; /* dead time, s */
} pdt_model_tc_t;

/* Integrator with a lag: Ki e^{-Td s} / (s (T s + 1)), Ki any finite value
 * (either sign), T > 0, Td >= 0. This is form (2) with b = 0. */
typedef struct pdt_model_integ {
    pdt_real_t Ki; /* integrating gain, output units per input unit per s */
    pdt_real_t T;  /* lag, s */
    pdt_real_t Td; /* dead time, s */
} pdt_model_integ_t;

typedef enum pdt_model_kind { PDT_MODEL_FOPDT = 1, PDT_MODEL_SOPDT = 2 } pdt_model_kind_t;

/* Either model, tagged. Fill `kind` and the matching member of `p`. */
typedef struct pdt_model {
    pdt_model_kind_t kind;
    union {
        pdt_model_fopdt_t fopdt;
        pdt_model_sopdt_t sopdt;
    } p;
} pdt_model_t;

/* Checks that a model is valid as documented on its type.
 * Returns PDT_OK, or PDT_ERR_ARG for NULL, an unknown kind, a non-finite or
 * out-of-domain parameter. */
pdt_status_t pdt_model_check(const pdt_model_t *m);

/* The dead time of either kind, in seconds (no checks). */
pdt_real_t pdt_model_dead_time(const pdt_model_t *m);

/* Conversions between SOPDT forms. Each checks its input and returns
 * PDT_ERR_ARG for NULL or an invalid input, PDT_ERR_NO_FORM when the target
 * form does not exist for this model; *out is written only on PDT_OK. */
pdt_status_t pdt_model_sopdt_from_natural(const pdt_model_natural_t *in, pdt_model_sopdt_t *out);
/* PDT_ERR_NO_FORM when b = 0 (no DC gain). */
pdt_status_t pdt_model_sopdt_to_natural(const pdt_model_sopdt_t *in, pdt_model_natural_t *out);
/* A real pair is accepted in either order (T1, T2 > 0); a complex pair needs
 * re = T1 > 0 and im = T2 > 0. */
pdt_status_t pdt_model_sopdt_from_tc(const pdt_model_tc_t *in, pdt_model_sopdt_t *out);
/* Real pair when a^2 >= 4b (zeta >= 1), else complex pair. PDT_ERR_NO_FORM
 * when b = 0. */
pdt_status_t pdt_model_sopdt_to_tc(const pdt_model_sopdt_t *in, pdt_model_tc_t *out);
pdt_status_t pdt_model_sopdt_from_integ(const pdt_model_integ_t *in, pdt_model_sopdt_t *out);
/* PDT_ERR_NO_FORM unless b = 0. */
pdt_status_t pdt_model_sopdt_to_integ(const pdt_model_sopdt_t *in, pdt_model_integ_t *out);

/* DC gain of a model. PDT_ERR_NO_FORM for an integrating SOPDT (b = 0). */
pdt_status_t pdt_model_dc_gain(const pdt_model_t *m, pdt_real_t *gain);

/* Unit-step response of the continuous model at times t[0..n-1] (s, any
 * order, negative allowed: the response is 0 before Td).
 * Returns PDT_ERR_ARG (NULL, invalid model), PDT_ERR_NONFINITE (a t is not
 * finite). n = 0 is a no-op returning PDT_OK. y must not overlap t. */
pdt_status_t pdt_model_step(const pdt_model_t *m, const pdt_real_t *t, size_t n, pdt_real_t *y);

/* Frequency response at angular frequencies w[0..n-1] (rad/s, >= 0):
 * magnitude |G(jw)| and phase arg G(jw) in radians, continuous (not wrapped
 * to (-pi, pi]) and including -w Td. A negative gain shows as magnitude
 * |K| (|k|) and the phase shifted by -pi, so the phase starts at -pi rather
 * than 0. Either output may be NULL if not wanted. At w = 0 an integrating
 * model has infinite magnitude (returned as +infinity; 0 if k = 0) and phase
 * -pi/2.
 * Returns PDT_ERR_ARG (NULL m or w, invalid model, w < 0) or
 * PDT_ERR_NONFINITE (a w is not finite). */
pdt_status_t pdt_model_freq(const pdt_model_t *m, const pdt_real_t *w, size_t n, pdt_real_t *mag,
                            pdt_real_t *phase);

#ifdef __cplusplus
}
#endif

#endif /* PDT_MODEL_H */
