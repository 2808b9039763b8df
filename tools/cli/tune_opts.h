/*
 * The tuning options shared by `tune`, `identify --tune` and
 * `autotune-sim`, the tuning of a model with the library's refusals as
 * messages, and the tuning's JSON.
 */
#ifndef PDTCLI_TUNE_OPTS_H
#define PDTCLI_TUNE_OPTS_H

#include "cli.h"
#include "json.h"

typedef struct tune_opts {
    int rule, form; /* pdt_tune_rule_t, pdt_tune_form_t */
    double tau_c, lambda, ms_max, deriv_filter, u_span, y_span, fit_min;
    int have_rule, have_tau_c, have_lambda, have_ms_max, have_filter, have_u_span, have_y_span,
        have_fit_min;
} tune_opts_t;

/* Appends the table rows of the tuning options to tab (room for 9);
 * without --rule and --form when rule_form is 0. Returns the rows added. */
size_t tune_opts_table(tune_opts_t *t, cli_opt_t *tab, int rule_form);
/* "RULE[:FORM]" of identify --tune. */
void tune_opts_spec(const char *cmd, const char *spec, tune_opts_t *t);
/* The checks between options (a knob of another rule, one span alone). */
void tune_opts_check(const char *cmd, const tune_opts_t *t);
void tune_opts_config(const tune_opts_t *t, pdt_tune_config_t *cfg);

/* Gains of m (fit: the identification's, 100 for a known model) into *r;
 * a refusal ends the program with its reason. A PID asked for that comes
 * out without derivative action is said on stderr. */
void tune_model(const char *cmd, const pdt_model_t *m, double fit, const tune_opts_t *t,
                pdt_tune_result_t *r);
/* tune_model that returns the library's status instead of ending the
 * program: on a refusal, the one-line reason (without the command's name)
 * into why[len], *r untouched. */
pdt_status_t tune_model_try(const char *cmd, const pdt_model_t *m, double fit, const tune_opts_t *t,
                            pdt_tune_result_t *r, char *why, size_t len);
/* Why the library refused (a hint after its status text). */
const char *tune_hint(pdt_status_t st, int rule, const pdt_model_t *m);

/* The value after "key": in the JSON object at b (its own keys, not
 * those of objects inside it; before e), or NULL. */
const char *tune_json_top(const char *b, const char *e, const char *key);
/* The flags of a model in identify's JSON object [b, e) (its "flags"
 * list, and a negative "fit"), as "at_bound, no_relation" into names.
 * Returns how many. */
int tune_json_flags(const char *b, const char *e, char *names, size_t len);
/* A flagged model (names from tune_json_flags, count of them) is not
 * tuned: refused with the flags named (exit 3), or with force tuned after
 * a warning. Returns 1 when the caller must end with status 3. */
int tune_check_flags(const char *cmd, const char *names, int count, int force);

/* The tuning as one JSON object. fig NULL: no model, the figures are null;
 * Ku, Pu echoed when finite. */
void tune_json(pdtcli_jbuf_t *jb, const tune_opts_t *t, const pdt_tune_result_t *r,
               const pdt_tune_figures_t *fig, double Ku, double Pu);

#endif /* PDTCLI_TUNE_OPTS_H */
