/*
 * The JSON of the pdtfit command line, written into caller buffers so that
 * the Python binding (through a shared library) prints exactly what the
 * program prints: numbers with 9 significant digits ("%.9g"), null where a
 * value is not finite or does not exist.
 */
#ifndef PDTCLI_JSON_H
#define PDTCLI_JSON_H

#include <stddef.h>

#include "pdt/pdt.h"
#include "uncert.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An identification result as one JSON object, no line end:
 * {"model":"fopdt","K",...,"evaluations"[,"f_band"][,"searches","runner_up",
 * "flags"][,"std"],"Ts","n"}, the keys of docs/cli.md. Ts: the sampling
 * period, s; n: the samples identified. With the record (u, y, not NULL)
 * it adds "std", the parameters' standard deviations (r->std, or for a
 * result without them, pdt_ls's, pdt_ident_uncertainty).
 * Returns the characters written (without the NUL), or -1 when len is too
 * small (buf then holds a truncated, NUL-terminated text). */
int pdtcli_ident_json(const pdt_ident_result_t *r, const pdt_real_t *u, const pdt_real_t *y,
                      double Ts, size_t n, char *buf, size_t len);

/* The same with the bootstrap's uncertainty (boot not NULL): "std", "cov"
 * and "ci95" (the 2.5 % and 97.5 % points) from its spread,
 * "uncertainty":"bootstrap" and "bootstrap_runs"; boot NULL: the Fisher
 * information's, "uncertainty":"fisher". */
int pdtcli_ident_json_boot(const pdt_ident_result_t *r, const pdt_real_t *u, const pdt_real_t *y,
                           double Ts, size_t n, const pdtcli_boot_t *boot, char *buf, size_t len);

/* A model alone ({"model",..} without operating point, cost, fit and
 * evaluations), as `pdtfit reduce` prints it. Returns as above. */
int pdtcli_model_json(const pdt_model_t *m, char *buf, size_t len);

/* A writer into a fixed buffer: appends until full, then remembers the
 * overflow. */
typedef struct pdtcli_jbuf {
    char *buf;
    size_t len, used;
    int over;
} pdtcli_jbuf_t;

void pdtcli_jb_init(pdtcli_jbuf_t *jb, char *buf, size_t len);
void pdtcli_jb_raw(pdtcli_jbuf_t *jb, const char *text);
void pdtcli_jb_printf(pdtcli_jbuf_t *jb, const char *fmt, ...)
#if defined(__MINGW32__)
    /* mingw-w64's own C99 printf (__USE_MINGW_ANSI_STDIO), as cli.h says. */
    __attribute__((format(gnu_printf, 2, 3)))
#elif defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void pdtcli_jb_num(pdtcli_jbuf_t *jb, double v);
/* ,"key":number */
void pdtcli_jb_key(pdtcli_jbuf_t *jb, const char *key, double v);
/* ,"key":"text" */
void pdtcli_jb_str(pdtcli_jbuf_t *jb, const char *key, const char *text);
/* ,"key":unsigned */
void pdtcli_jb_uint(pdtcli_jbuf_t *jb, const char *key, unsigned long v);
/* The model object; r NULL: the model's keys only. */
void pdtcli_jb_model(pdtcli_jbuf_t *jb, const pdt_model_t *m, const pdt_ident_result_t *r);
int pdtcli_jb_done(const pdtcli_jbuf_t *jb);
/* Several records' keys after an identification's (docs/several-records.md):
 * the uncertainty null, "record_fit" (each record's file, from names when
 * not NULL, n, Ts, u0, y0, fit, cost, x0, dx0, drift), "records" and
 * "samples". A status of pdt_ident_record_result on error. */
pdt_status_t pdtcli_jb_several(pdtcli_jbuf_t *jb, pdt_ident_t *ctx, const char *const *names,
                               size_t count);
/* The tuning object of `pdtfit tune` into jb (see json.c). */
void pdtcli_jb_tune(pdtcli_jbuf_t *jb, const char *rule, const char *form, int knob_tau_c,
                    int knob_lambda, const pdt_tune_result_t *r, const pdt_tune_figures_t *fig,
                    double span, double Ku, double Pu);

/* ,"std":{...},"cov":{...}: the uncertainty sd of m's own parameters as
 * the printed parameters' (pdt_ident_std_printed), under the JSON's names
 * and in its order; null where one is absent or undetermined. */
void pdtcli_jb_std(pdtcli_jbuf_t *jb, const pdt_model_t *m, const pdt_ident_std_t *sd);

/* ,"order":{"kept",...,"fopdt":{...},"sopdt":{...}} of --model auto: the
 * evidence each model had (r, v: FOPDT then SOPDT), in the order
 * pdt_ident_select_order weighs it. */
void pdtcli_jb_order(pdtcli_jbuf_t *jb, pdt_model_kind_t kept, const pdt_ident_result_t r[2],
                     const pdt_validate_result_t v[2]);

#ifdef __cplusplus
}
#endif

#endif /* PDTCLI_JSON_H */
