/* The option parser and the messages of the command line (cli.h). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

const char *const cli_model_names[] = {"fopdt", "sopdt", NULL};
const char *const cli_rule_names[] = {"simc", "imc", "amigo", "zn", NULL};
const char *const cli_form_names[] = {"pi", "pid", NULL};

const char *cli_model_str(pdt_model_kind_t kind)
{
    return kind == PDT_MODEL_FOPDT ? "fopdt" : "sopdt";
}

void cli_fail(int status, const char *fmt, ...)
{
    va_list ap;
    fflush(stdout);
    fputs("pdtfit: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(status);
}

void cli_warn(const char *fmt, ...)
{
    va_list ap;
    fputs("pdtfit: warning: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void cli_flush(void)
{
    if (fflush(stdout) != 0 || ferror(stdout)) cli_fail(EXIT_REFUSED, "cannot write the result");
}

/* Decimal digits only: strtoull alone would accept signs and blanks. */
int cli_parse_u64(const char *s, uint64_t *out)
{
    uint64_t v = 0;
    if (*s == '\0') return -1;
    for (; *s; s++) {
        if (*s < '0' || *s > '9') return -1;
        unsigned d = (unsigned)(*s - '0');
        if (v > (UINT64_MAX - d) / 10u) return -1;
        v = v * 10u + d;
    }
    *out = v;
    return 0;
}

int cli_parse_real(const char *s, double *out)
{
    char *stop;
    errno = 0;
    double v = strtod(s, &stop);
    if (stop == s || *stop != '\0' || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

int cli_choice(const char *s, const char *const *list)
{
    for (int k = 0; list[k]; k++) {
        size_t i = 0;
        for (; s[i] && list[k][i]; i++) {
            char c = s[i];
            if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
            if (c != list[k][i]) break;
        }
        if (s[i] == '\0' && list[k][i] == '\0') return k;
    }
    return -1;
}

static int check_real(cli_check_t check, double v)
{
    switch (check) {
    case CHK_GE0:
        return v >= 0.0;
    case CHK_GT0:
        return v > 0.0;
    case CHK_NONZERO:
        return v != 0.0;
    case CHK_LIMIT:
        return v == 0.0 || v > 1.0;
    case CHK_FILTER:
        return v == 0.0 || v >= 1.0;
    default:
        return 1;
    }
}

/* "a, b or c" of a choice list. */
static void list_choices(const char *const *list, char *buf, size_t len)
{
    size_t j = 0;
    buf[0] = '\0';
    for (int k = 0; list[k] && j < len; k++)
        j += (size_t)snprintf(buf + j, len - j, "%s%s",
                              k == 0        ? ""
                              : list[k + 1] ? ", "
                                            : " or ",
                              list[k]);
}

/* A comma-separated list of finite numbers: count, or -1. */
static int parse_list(const char *s, double *out, int max)
{
    char buf[64];
    int count = 0;
    for (;;) {
        const char *comma = strchr(s, ',');
        size_t len = comma ? (size_t)(comma - s) : strlen(s);
        if (len == 0 || len >= sizeof buf || count >= max) return -1;
        memcpy(buf, s, len);
        buf[len] = '\0';
        if (cli_parse_real(buf, &out[count]) != 0) return -1;
        count++;
        if (!comma) return count;
        s = comma + 1;
    }
}

static void store_list(const cli_parser_t *p, const cli_opt_t *o, const char *value)
{
    cli_list_t *l = o->dest;
    const int before = (o->flags & CLI_REPEAT) ? l->n : 0;
    const int got = parse_list(value, l->v + before, CLI_MAX_LIST - before);
    if (got < 0)
        cli_fail(EXIT_USAGE, "%s: %s needs 1 to %d numbers separated by commas%s, got '%s'", p->cmd,
                 o->name, CLI_MAX_LIST, before ? " in all" : "", value);
    l->n = before + got;
    for (int k = before; k < l->n; k++)
        if (!check_real(o->check, l->v[k]))
            cli_fail(EXIT_USAGE, "%s: %s: %s, got %.9g", p->cmd, o->name, o->what, l->v[k]);
}

static void store(const cli_parser_t *p, const cli_opt_t *o, const char *value)
{
    double r;
    uint64_t u;
    int k;
    switch (o->kind) {
    case OPT_REAL:
        if (cli_parse_real(value, &r) != 0 || !check_real(o->check, r) ||
            ((o->flags & CLI_REAL_FITS) && !isfinite((double)(pdt_real_t)r)))
            cli_fail(EXIT_USAGE, "%s: %s needs %s, got '%s'", p->cmd, o->name,
                     o->what ? o->what : "a finite number", value);
        *(double *)o->dest = r;
        break;
    case OPT_UINT:
        if (cli_parse_u64(value, &u) != 0 || u < o->lo || u > o->hi ||
            ((o->flags & CLI_EVEN) && u % 2u))
            cli_fail(EXIT_USAGE, "%s: %s needs %s, got '%s'", p->cmd, o->name, o->what, value);
        *(uint64_t *)o->dest = u;
        break;
    case OPT_CHOICE:
        k = cli_choice(value, o->choices);
        if (k < 0) {
            char list[160];
            list_choices(o->choices, list, sizeof list);
            cli_fail(EXIT_USAGE, "%s: unknown %s '%s' (%s)", p->cmd, o->what, value, list);
        }
        *(int *)o->dest = k + (int)o->lo;
        break;
    case OPT_TEXT:
        *(const char **)o->dest = value;
        break;
    case OPT_LIST:
        store_list(p, o, value);
        break;
    default:
        *(int *)o->dest = 1;
        break;
    }
    if (o->given) *o->given = 1;
}

static int find_opt(const cli_parser_t *p, const char *name, size_t len)
{
    for (size_t k = 0; k < p->n_opt; k++)
        if (strlen(p->opt[k].name) == len && strncmp(p->opt[k].name, name, len) == 0) return (int)k;
    return -1;
}

static void positional(cli_parser_t *p, const char *arg)
{
    if (!p->file)
        cli_fail(EXIT_USAGE, "%s: unexpected argument '%s' (%s reads no file)", p->cmd, arg,
                 p->cmd);
    if (*p->file && p->more && *p->n_more < p->max_more) {
        p->more[(*p->n_more)++] = arg;
        return;
    }
    if (*p->file && p->more)
        cli_fail(EXIT_USAGE, "%s: at most %zu FILEs, got '%s' after them", p->cmd, p->max_more + 1u,
                 arg);
    if (*p->file)
        cli_fail(EXIT_USAGE, "%s: one FILE only, got '%s' after '%s'", p->cmd, arg, *p->file);
    *p->file = arg;
}

/* One option at argv[*i]; takes its value from the next argument or after
 * '='. */
static void take(cli_parser_t *p, int argc, char **argv, int *i)
{
    const char *arg = argv[*i], *eq = strchr(arg, '=');
    const size_t len = eq ? (size_t)(eq - arg) : strlen(arg);
    const int k = find_opt(p, arg, len);
    if (k < 0)
        cli_fail(EXIT_USAGE, "%s: unknown option '%.*s' (see pdtfit %s --help)", p->cmd, (int)len,
                 arg, p->cmd);
    const cli_opt_t *o = &p->opt[k];
    if (p->seen[k] && !(o->flags & CLI_REPEAT))
        cli_fail(EXIT_USAGE, "%s: %s given twice", p->cmd, o->name);
    p->seen[k] = 1;
    const char *value = eq ? eq + 1 : NULL;
    if (o->kind == OPT_FLAG && value)
        cli_fail(EXIT_USAGE, "%s: %s takes no value", p->cmd, o->name);
    if (o->kind != OPT_FLAG && !value) {
        if (*i + 1 >= argc) cli_fail(EXIT_USAGE, "%s: %s needs a value", p->cmd, o->name);
        value = argv[++*i];
    }
    store(p, o, value);
}

void cli_parse(cli_parser_t *p, int argc, char **argv)
{
    if (p->n_opt > CLI_MAX_OPTS) cli_fail(EXIT_REFUSED, "%s: option table too long", p->cmd);
    memset(p->seen, 0, sizeof p->seen);
    /* Help wins over any mistake elsewhere on the line. */
    for (int i = 0; i < argc && strcmp(argv[i], "--") != 0; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) cli_help(p->help);
    int only_files = 0;
    for (int i = 0; i < argc; i++) {
        const char *arg = argv[i];
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            positional(p, arg);
        } else if (strcmp(arg, "--") == 0) {
            only_files = 1;
        } else if (arg[1] != '-' && !p->file) {
            positional(p, arg);
        } else if (arg[1] != '-') {
            cli_fail(EXIT_USAGE, "%s: unknown option '%s' (see pdtfit %s --help)", p->cmd, arg,
                     p->cmd);
        } else {
            take(p, argc, argv, &i);
        }
    }
}

int cli_given(const cli_parser_t *p, const char *name)
{
    const int k = find_opt(p, name, strlen(name));
    return k >= 0 && p->seen[k];
}
