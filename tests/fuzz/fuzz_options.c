/*
 * Fuzz target: the command line's option parser (tools/cli/opt.c) on
 * fuzzed argument vectors, against a table with every kind of option and
 * check. The parser ends the program on a usage error or after help; here
 * its exit is a jump back (opt.c and help.c are compiled with exit mapped
 * to fuzz_exit, see CMakeLists.txt); run it with -close_fd_mask=3 so that
 * its messages do not flood the log (tests/fuzz/run.sh does).
 * Contracts checked: a parse that returns took every value within its
 * declared check (finite reals, ranges, choices, list lengths), marked
 * each given option, and took each option at most once; a refused parse
 * ends with the usage status, or 0 after help.
 */
#include <setjmp.h>

#include "cli.h"
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
void fuzz_exit(int status);

static jmp_buf g_back;
static int g_status;

void fuzz_exit(int status)
{
    g_status = status;
    longjmp(g_back, 1);
}

static const char *const g_choices[] = {"fopdt", "sopdt", "auto", NULL};

typedef struct vals {
    int flag, choice;
    double real_any, real_ge0, real_gt0, real_nz, real_lim, real_filt;
    uint64_t count;
    const char *text;
    cli_list_t list;
    int given[9];
} vals_t;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* The input as up to 24 NUL-separated arguments. */
    static char buf[4096];
    char *argv[25];
    int argc = 0;
    size = size < sizeof buf - 1u ? size : sizeof buf - 1u;
    memcpy(buf, data, size);
    buf[size] = '\0';
    for (size_t i = 0; i <= size && argc < 24;) {
        argv[argc++] = buf + i;
        i += strlen(buf + i) + 1u;
    }
    argv[argc] = NULL;
    static vals_t v;
    memset(&v, 0, sizeof v);
    const char *file = NULL;
    const cli_opt_t tab[] = {
        {"--flag", OPT_FLAG, &v.flag, &v.given[0], CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--choice", OPT_CHOICE, &v.choice, &v.given[1], CHK_ANY, 1, 0, g_choices, "model", 0},
        {"--any", OPT_REAL, &v.real_any, &v.given[2], CHK_ANY, 0, 0, NULL, "a number", 0},
        {"--ge0", OPT_REAL, &v.real_ge0, &v.given[3], CHK_GE0, 0, 0, NULL, ">= 0", CLI_REAL_FITS},
        {"--gt0", OPT_REAL, &v.real_gt0, &v.given[4], CHK_GT0, 0, 0, NULL, "> 0", 0},
        {"--nz", OPT_REAL, &v.real_nz, NULL, CHK_NONZERO, 0, 0, NULL, "!= 0", 0},
        {"--lim", OPT_REAL, &v.real_lim, NULL, CHK_LIMIT, 0, 0, NULL, "0 or > 1", 0},
        {"--filt", OPT_REAL, &v.real_filt, NULL, CHK_FILTER, 0, 0, NULL, "0 or >= 1", 0},
        {"--count", OPT_UINT, &v.count, &v.given[5], CHK_ANY, 2, 1000, NULL, "2 .. 1000", CLI_EVEN},
        {"--text", OPT_TEXT, &v.text, &v.given[6], CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--list", OPT_LIST, &v.list, &v.given[7], CHK_GT0, 0, 0, NULL, "> 0", 0},
    };
    /* identify's further records: up to three more positional arguments. */
    const char *more[3] = {NULL, NULL, NULL};
    size_t n_more = 0u;
    const size_t n_tab = sizeof tab / sizeof tab[0];
    const size_t max_more = sizeof more / sizeof more[0];
    cli_parser_t p = {"identify", CMD_IDENTIFY, tab, n_tab, &file, {0}, more, &n_more, max_more};
    if (setjmp(g_back) != 0) {
        FZ_CHECK(g_status == EXIT_USAGE || g_status == 0);
        return 0;
    }
    cli_parse(&p, argc, argv);
    FZ_CHECK(isfinite(v.real_any) && isfinite(v.real_ge0) && v.real_ge0 >= 0.0);
    FZ_CHECK(!v.given[4] || v.real_gt0 > 0.0);
    FZ_CHECK(isfinite(v.real_nz) && isfinite(v.real_lim) && isfinite(v.real_filt));
    FZ_CHECK(v.real_lim == 0.0 || v.real_lim > 1.0);
    FZ_CHECK(v.real_filt == 0.0 || v.real_filt >= 1.0);
    FZ_CHECK(!v.given[5] || (v.count >= 2u && v.count <= 1000u && v.count % 2u == 0u));
    FZ_CHECK(!v.given[1] || (v.choice >= 1 && v.choice <= 3));
    FZ_CHECK(v.list.n >= 0 && v.list.n <= CLI_MAX_LIST);
    for (int i = 0; i < v.list.n; i++) {
        FZ_CHECK(isfinite(v.list.v[i]) && v.list.v[i] > 0.0);
    }
    FZ_CHECK(n_more <= max_more);
    FZ_CHECK(n_more == 0u || file != NULL);
    for (size_t i = 0; i < n_more; i++) {
        FZ_CHECK(more[i] != NULL);
    }
    for (size_t i = 0; i < p.n_opt; i++) {
        FZ_CHECK(p.seen[i] == 0 || p.seen[i] == 1);
    }
    return 0;
}
