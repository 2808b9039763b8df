/*
 * The entry points the Python package pdtfit loads with ctypes
 * (python/pdtfit/_lib.py mirrors these structs; change both together).
 * Every function returns a pdt_status_t value (0 ok, negative error) or
 * PDTPY_ERR_NOMEM, except where it says otherwise.
 */
#ifndef PDTPY_H
#define PDTPY_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#define PDTPY_API __declspec(dllexport)
#else
#define PDTPY_API __attribute__((visibility("default")))
#endif

/* The host ran out of memory or the JSON buffer was too small. */
#define PDTPY_ERR_NOMEM (-1000)

/* How pdtpy_model_make reads x1, x2 of a SOPDT. */
#define PDTPY_SOPDT_NATURAL 0 /* wn, zeta */
#define PDTPY_SOPDT_TC      1 /* tau1, tau2 */
#define PDTPY_SOPDT_INTEG   2 /* Ki in K, T in x1 */

/* pdtpy_ident_opts_t.method: `pdtfit identify --method`. */
#define PDTPY_METHOD_GA   0
#define PDTPY_METHOD_ELMS 1
#define PDTPY_METHOD_EIV  2

/* pdtpy_ident_opts_t.model: both models, the order chosen by the evidence
 * (`pdtfit identify --model auto`). */
#define PDTPY_MODEL_AUTO 3

/* identify's options; NaN or a negative weight means the library default. */
typedef struct pdtpy_ident_opts {
    int method; /* PDTPY_METHOD_*; ELMS and EIV read model and td_max only */
    int model;  /* pdt_model_kind_t, or PDTPY_MODEL_AUTO (GA only) */
    int cost;   /* pdt_cost_kind_t */
    int weight; /* pdt_weight_kind_t, -1 default */
    int integer_delay;
    uint64_t seed;
    uint32_t evaluations; /* 0 default */
    uint32_t population;  /* 0 default */
    double td_max, f_lo, f_hi, phi_t, phi_f;
    uint32_t coarse;    /* 0 automatic */
    double u_before;    /* the input before the record; NaN: not given */
    int refuse_missing; /* a non-finite y is refused, not left out */
    int initial;        /* pdt_ident_initial_t */
    int offset;         /* pdt_ident_offset_t */
    int uncertainty;    /* 0 auto (the bootstrap for a SOPDT), 1 fisher, 2 bootstrap */
    uint32_t boot_runs; /* 0: PDTCLI_BOOT_RUNS */
    int drift;          /* a linear drift fitted too */
} pdtpy_ident_opts_t;

typedef struct pdtpy_tune_opts {
    int rule, form;                             /* pdt_tune_rule_t, pdt_tune_form_t */
    double tau_c, lambda, ms_max, deriv_filter; /* NaN: default */
    double fit, fit_min;                        /* %; NaN: 100, the default */
    double span;                                /* y_span / u_span for "percent"; NaN: none */
    double Ku, Pu;                              /* zn from a relay's ultimate point; NaN: none */
} pdtpy_tune_opts_t;

/* The options of the command line's reader (pdtcli_csv_opts_t). */
typedef struct pdtpy_csv_opts {
    const char *t_col, *u_col, *y_col; /* name or 1-based index; NULL default */
    char sep, decimal;                 /* 0: detect, '.' */
    unsigned skip;
    int time_unit; /* -1 the header's (else s), 0 s, 1 ms, 2 us, 3 min, 4 h */
    int resample;
    double fs;                /* 0: from the time column */
    int units_row;            /* 1: a units row under the header */
    const char *time_format;  /* NULL: detected */
    const double *bad_values; /* declared bad values, n_bad_values of them */
    size_t n_bad_values;
    int bad_rows; /* 0: missing samples, 1: refused */
} pdtpy_csv_opts_t;

/* The record read (pdtcli_series_t): u, y malloc'ed, free with
 * pdtpy_series_free. */
typedef struct pdtpy_series {
    double *u, *y;
    size_t n;
    double Ts;            /* s */
    unsigned jitter_warn; /* time stamps off the grid within the tolerance */
    unsigned filled;      /* samples filled by resampling */
    size_t units_row;     /* the line of a units row found and skipped, 0 */
} pdtpy_series_t;

/* The library's description of a status (pdt_status_str). */
PDTPY_API const char *pdtpy_status_str(int status);
/* The status's identifier (pdt_status_name: "PDT_ERR_NO_EXCITATION"), as
 * the command line's JSON names it. */
PDTPY_API const char *pdtpy_status_name(int status);
PDTPY_API int pdtpy_real_size(void);
PDTPY_API int pdtpy_model_make(int kind, int form, double K, double x1, double x2, double Td,
                               double *out);
/* Characters written, or -1. */
PDTPY_API int pdtpy_model_json(const double *model, char *buf, size_t len);
PDTPY_API int pdtpy_identify(const double *u, const double *y, size_t n, double Ts,
                             const pdtpy_ident_opts_t *o, double *model, char *json,
                             size_t json_len);
/* Several records (count 2 .. PDT_IDENT_MAX_RECORDS) of one process: u[r],
 * y[r] of n[r] samples every Ts[r] s; the options as pdtpy_identify's
 * (GA, the simulation criterion), every screen off. */
PDTPY_API int pdtpy_identify_many(const double *const *u, const double *const *y, const size_t *n,
                                  const double *Ts, size_t count, const pdtpy_ident_opts_t *o,
                                  double *model, char *json, size_t json_len);
PDTPY_API int pdtpy_simulate(const double *model, double Ts, const double *u, const double *y,
                             size_t n, double u0, double y0, double *ysim);
/* model NULL: no model (zn from Ku and Pu only, the figures null). */
PDTPY_API int pdtpy_tune(const double *model, const pdtpy_tune_opts_t *o, double *ms_refused,
                         char *json, size_t json_len);
/* The index of the first gross outlier of x (pdt_cost_outlier), n: none. */
PDTPY_API size_t pdtpy_outlier(const double *x, size_t n);
PDTPY_API int pdtpy_reduce(int method, int kind, double gain, const double *lags, size_t n_lags,
                           const double *zeros, size_t n_zeros, double delay, double h,
                           double *model, char *json, size_t json_len);
/* 0 ok, -1 with a message in err. */
PDTPY_API int pdtpy_read_series(const char *path, const pdtpy_csv_opts_t *o, pdtpy_series_t *out,
                                char *err, size_t errlen);
PDTPY_API void pdtpy_series_free(pdtpy_series_t *s);

#endif /* PDTPY_H */
