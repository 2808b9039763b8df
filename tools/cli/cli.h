/*
 * The shared layer of the pdtfit command line: exit statuses, messages, and
 * the one option parser every subcommand uses. A subcommand describes its
 * options as a table of cli_opt_t (name, kind, destination, check) and calls
 * cli_parse once; the parser converts and checks each value, refuses an
 * unknown or repeated option, and prints the subcommand's help on -h.
 *
 * Host code: messages go to stderr and errors end the program.
 */
#ifndef PDTCLI_CLI_H
#define PDTCLI_CLI_H

#include <stddef.h>
#include <stdint.h>

#include "pdt/pdt.h"

/* Exit statuses (docs/cli.md). */
#define EXIT_REFUSED 1 /* the library refused, or the host failed */
#define EXIT_USAGE   2 /* bad usage, an unreadable or malformed file */
#define EXIT_SUSPECT                                                                               \
    3 /* a model printed, but with a warning that it is
                        * probably wrong (negative fit, on a bound) */
/* identify --tune: the model printed, its tuning refused (the JSON's "tune"
 * holds the refusal's status and reason) */
#define EXIT_TUNE_REFUSED 4

#define CLI_MAX_LIST 64
#define CLI_MAX_OPTS 64

#if defined(__GNUC__)
/* mingw-w64 builds print with its own C99 printf (__USE_MINGW_ANSI_STDIO,
 * CMakeLists.txt), whose formats are gnu_printf's, not the Windows C
 * runtime's. */
#ifdef __MINGW32__
#define CLI_PRINTF_FORMAT gnu_printf
#else
#define CLI_PRINTF_FORMAT printf
#endif
#define CLI_NORETURN_PRINTF(f, a) __attribute__((noreturn, format(CLI_PRINTF_FORMAT, f, a)))
#define CLI_PRINTF(f, a)          __attribute__((format(CLI_PRINTF_FORMAT, f, a)))
#define CLI_NORETURN              __attribute__((noreturn))
#else
#define CLI_NORETURN_PRINTF(f, a)
#define CLI_PRINTF(f, a)
#define CLI_NORETURN
#endif

/* "pdtfit: <message>" on stderr, then exit(status). */
void cli_fail(int status, const char *fmt, ...) CLI_NORETURN_PRINTF(2, 3);
/* "pdtfit: warning: <message>" on stderr. */
void cli_warn(const char *fmt, ...) CLI_PRINTF(1, 2);
/* Flushes stdout; a write error ends the program with EXIT_REFUSED. */
void cli_flush(void);

typedef enum cli_kind {
    OPT_FLAG,   /* int: 1 when given; takes no value */
    OPT_REAL,   /* double, finite, checked by `check` */
    OPT_UINT,   /* uint64_t, decimal digits, in [lo, hi] */
    OPT_CHOICE, /* int: index in `choices`, compared case-insensitively */
    OPT_TEXT,   /* const char *: the value as given */
    OPT_LIST    /* cli_list_t: finite numbers separated by commas */
} cli_kind_t;

typedef enum cli_check {
    CHK_ANY,     /* any finite number */
    CHK_GE0,     /* >= 0 */
    CHK_GT0,     /* > 0 */
    CHK_NONZERO, /* != 0 */
    CHK_LIMIT,   /* 0 or > 1 (an Ms limit) */
    CHK_FILTER   /* 0 or >= 1 (a filter ratio) */
} cli_check_t;

/* flags */
#define CLI_EVEN      1u /* OPT_UINT: even */
#define CLI_REAL_FITS 2u /* OPT_REAL: finite as pdt_real_t too */
#define CLI_GA_ONLY   4u /* identify: an option of --method ga only */
#define CLI_REPEAT    8u /* OPT_LIST: may be given again, the values added */

typedef struct cli_list {
    double v[CLI_MAX_LIST];
    int n;
} cli_list_t;

typedef struct cli_opt {
    const char *name; /* "--model" */
    cli_kind_t kind;
    void *dest;                 /* see cli_kind_t */
    int *given;                 /* set to 1 when given; may be NULL */
    cli_check_t check;          /* OPT_REAL, OPT_LIST (each value) */
    uint64_t lo, hi;            /* OPT_UINT: the range; OPT_CHOICE: lo is
                                 * added to the index stored */
    const char *const *choices; /* OPT_CHOICE: NULL-terminated */
    const char *what;           /* what the value must be, for messages
                                 * ("a dead time >= 0 s"); OPT_CHOICE: the
                                 * noun ("model") */
    unsigned flags;
} cli_opt_t;

typedef enum cli_cmd {
    CMD_ALL,
    CMD_IDENTIFY,
    CMD_REDUCE,
    CMD_TUNE,
    CMD_AUTOTUNE,
    CMD_MONITOR
} cli_cmd_t;

typedef struct cli_parser {
    const char *cmd;      /* "identify", for messages */
    cli_cmd_t help;       /* the help -h prints */
    const cli_opt_t *opt; /* the table */
    size_t n_opt;
    const char **file; /* the one positional argument, or NULL: none */
    int seen[CLI_MAX_OPTS];
    /* Further positional arguments after the first (identify's further
     * records), or NULL: one only. */
    const char **more;
    size_t *n_more;
    size_t max_more;
} cli_parser_t;

/* Parses argv[0 .. argc) against p's table, storing every value; ends the
 * program on a usage error or after printing help. */
void cli_parse(cli_parser_t *p, int argc, char **argv);
/* Whether the option of that name was given (after cli_parse). */
int cli_given(const cli_parser_t *p, const char *name);

/* A whole decimal number: 0 ok, -1 not one. */
int cli_parse_u64(const char *s, uint64_t *out);
/* A finite number: 0 ok, -1 not one. */
int cli_parse_real(const char *s, double *out);
/* Case-insensitive index of s in the NULL-terminated list, or -1. */
int cli_choice(const char *s, const char *const *list);

/* The help: usage and the section of one subcommand (CMD_ALL: all). */
void cli_help(cli_cmd_t which) CLI_NORETURN;
extern const char cli_usage[];

/* Names, in the enum orders of the library. */
extern const char *const cli_model_names[]; /* fopdt, sopdt */
extern const char *const cli_rule_names[];  /* simc, imc, amigo, zn */
extern const char *const cli_form_names[];  /* pi, pid */
/* "fopdt" or "sopdt" of a pdt_model_kind_t. */
const char *cli_model_str(pdt_model_kind_t kind);

/* The program's argv[0], set by main (to find the plot script). */
extern const char *cli_argv0;

/* Subcommands. */
int cmd_identify(int argc, char **argv);
int cmd_reduce(int argc, char **argv);
int cmd_tune(int argc, char **argv);
int cmd_autotune_sim(int argc, char **argv);
int cmd_monitor(int argc, char **argv);

#endif /* PDTCLI_CLI_H */
