/* The model of a JSON file as identify (or autotune-sim) prints it, for
 * the subcommands that read one (tune --from, monitor --model). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model_json.h"
#include "tune_opts.h"

/* The value of "key" among the object's own keys in [b, e), or NULL. */
static const char *json_value(const char *b, const char *e, const char *key)
{
    return tune_json_top(b, e, key);
}

/* The number of "key" in [b, e), NAN when absent or null. */
static double json_number(const char *b, const char *e, const char *key)
{
    const char *v = json_value(b, e, key);
    char *stop;
    double x = v ? strtod(v, &stop) : (double)NAN;
    return v && stop != v ? x : (double)NAN;
}

static int json_is(const char *b, const char *e, const char *key, const char *text)
{
    const char *v = json_value(b, e, key);
    const size_t len = strlen(text);
    return v && v + len + 2 <= e && *v == '"' && memcmp(v + 1, text, len) == 0 && v[len + 1] == '"';
}

char *pdtcli_slurp(const char *path)
{
    FILE *in = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!in) return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap + 1);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n, in)) > 0) {
        n += got;
        if (n == cap) {
            char *bigger = realloc(buf, 2 * cap + 1);
            if (!bigger) free(buf);
            buf = bigger;
            cap *= 2;
        }
    }
    if (in != stdin) fclose(in);
    if (buf) buf[n] = '\0';
    return buf;
}

/* The model of identify's JSON (or of autotune-sim's "ident"): its kind
 * and the numbers that give it exactly (K, tau, Td; or K or Ki, a, b, Td),
 * and its flags. */
int pdtcli_model_from_json(const char *cmd, const char *path, pdt_model_t *m, double *fit,
                           char *flags, size_t flags_len)
{
    const char *name = strcmp(path, "-") == 0 ? "stdin" : path;
    char *text = pdtcli_slurp(path);
    if (!text) cli_fail(EXIT_USAGE, "%s: cannot read %s", cmd, name);
    const char *b = json_value(text, text + strlen(text), "ident"), *e;
    b = b && *b == '{' ? b : text;
    e = text + strlen(text);
    const int fopdt = json_is(b, e, "model", "fopdt"), sopdt = json_is(b, e, "model", "sopdt");
    if (!fopdt && !sopdt)
        cli_fail(EXIT_USAGE, "%s: %s holds no model (expected the JSON of pdtfit identify)", cmd,
                 name);
    const int n_flags = flags != NULL ? tune_json_flags(b, e, flags, flags_len) : 0;
    const double K = json_number(b, e, "K"), Td = json_number(b, e, "Td");
    *fit = json_number(b, e, "fit");
    memset(m, 0, sizeof *m);
    if (fopdt) {
        m->kind = PDT_MODEL_FOPDT;
        m->p.fopdt.K = (pdt_real_t)K;
        m->p.fopdt.tau = (pdt_real_t)json_number(b, e, "tau");
        m->p.fopdt.Td = (pdt_real_t)Td;
    } else {
        const double a = json_number(b, e, "a"), bb = json_number(b, e, "b");
        const double Ki = json_number(b, e, "Ki");
        m->kind = PDT_MODEL_SOPDT;
        m->p.sopdt.a = (pdt_real_t)a;
        m->p.sopdt.b = (pdt_real_t)bb;
        m->p.sopdt.k = (pdt_real_t)(bb > 0.0 ? K * bb : Ki * a);
        m->p.sopdt.Td = (pdt_real_t)Td;
    }
    free(text);
    if (pdt_model_check(m) != PDT_OK)
        cli_fail(EXIT_USAGE, "%s: the model in %s is incomplete or invalid", cmd, name);
    if (!isfinite(*fit)) *fit = 100.0;
    return n_flags;
}
