/*
 * pdtfit: the command line. `pdtfit identify --model fopdt FILE.csv` reads
 * one record of a plant (input u, output y, optionally time t), identifies
 * a FOPDT or SOPDT model with the library and prints it as one JSON object.
 *
 * Exit status: 0 success, 1 the library refused the data (or the host ran
 * out of memory), 2 a usage or input error. Every error is one line on
 * stderr starting "pdtfit: "; nothing is printed on stdout then.
 */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "pdt/pdt.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_ls.h"
#include "pdt/pdt_reduce.h"

#define EXIT_REFUSED 1
#define EXIT_USAGE 2

/* Relative tolerance on the sampling period: t against a uniform grid, and
 * --fs against t. */
#define TS_TOLERANCE 0.01

static const char usage_line[] =
    "usage: pdtfit identify --model fopdt|sopdt [--method ga|elms|eiv] [options] FILE.csv\n"
    "       pdtfit reduce --method skogestad|sung --model fopdt|sopdt --gain K\n"
    "                     --lags T1,T2,... [--zeros Z1,...] [--delay D] [--h H]\n"
    "       pdtfit --help | --version\n";

/* In paragraphs: ISO C99 compilers need only take 4095-character strings. */
static const char *const help_text[] = {
    "\n",
    "Identifies a first- or second-order-plus-dead-time model of a process\n"
    "from one recorded test (Yang and Seested 2013: a genetic-algorithm\n"
    "search followed by a local refinement) and prints it as one JSON object.\n"
    "\n",
    "Options of identify:\n"
    "  --model fopdt|sopdt   the model (required):\n"
    "                          fopdt  K e^(-Td s) / (tau s + 1)\n"
    "                          sopdt  K wn^2 e^(-Td s) / (s^2 + 2 zeta wn s + wn^2)\n"
    "  --method ga|elms|eiv  how (default ga):\n"
    "                          ga    genetic-algorithm search and local refinement\n"
    "                                of the criterion --cost\n"
    "                          elms  least squares of the one-step prediction model\n"
    "                                for every whole-sample dead time, the best kept\n"
    "                                (the paper's ELMS); fast, but output noise\n"
    "                                biases it like --cost prediction\n"
    "                          eiv   the same scan by instrumental variables\n"
    "                                (E-IV-LMS): not biased by output noise\n"
    "                        elms and eiv give Td in whole samples and take none of\n"
    "                        --cost, --seed, --evaluations, --population\n"
    "  --td-max S            largest dead time searched, s, >= 0 (ga: > 0). Default:\n"
    "                        ga a third of the record, elms/eiv a quarter\n"
    "  --cost KIND           the criterion minimised (default simulation):\n"
    "                          simulation  output error: the model is run on u alone\n"
    "                                      and compared with y. Unbiased under\n"
    "                                      measurement noise: use it on plant data.\n"
    "                          prediction  the paper's one-step prediction from the\n"
    "                                      measured y (equation error); measurement\n"
    "                                      noise biases it (gain and time constant).\n"
    "                          frequency   fits |G(jw)| to the spectra of u and y.\n"
    "                                      Magnitudes cannot see the dead time or\n"
    "                                      the sign of the gain: those come from a\n"
    "                                      scan of the simulation cost.\n"
    "                          combined    simulation + frequency (the paper's\n"
    "                                      combined cost, with the unbiased time\n"
    "                                      part): the time part fixes the dead time.\n"
    "                        frequency and combined need a record that also ends at\n"
    "                        rest (u back at u[0], y settled).\n"
    "  --seed N              seed of the search's random numbers (default 1); the\n"
    "                        same seed, data and build give the same output\n"
    "  --fs HZ               sampling frequency; required without a t column,\n"
    "                        else it must agree with t within 1%\n",
    /* NULL: the lines that show the library's own defaults go here. */
    NULL,
    "  --integer-delay       dead time in whole samples, as in the paper (default:\n"
    "                        fractional dead time with an exact sampled model)\n"
    "  -h, --help            this text\n"
    "\n",
    "FILE.csv ('-' reads standard input):\n"
    "  Comma separated, a header row first. Columns named t, u and y (any case,\n"
    "  blanks around names ignored) are read, other columns are ignored:\n"
    "    t  time in seconds, increasing and uniform (each t within 1% of a\n"
    "       sampling period of the uniform grid from the first to the last t);\n"
    "       optional when --fs is given\n"
    "    u  process input (e.g. valve opening), engineering units\n"
    "    y  process output (e.g. temperature), engineering units\n"
    "  Every t, u, y cell must be a finite number; every row must have as many\n"
    "  fields as the header; at least 16 rows. The record must start with the\n"
    "  process at rest: u[0] is taken as the input operating point.\n"
    "\n",
    "Output: one JSON object on one line, numbers with 9 significant digits,\n"
    "null where a value does not exist.\n"
    "  fopdt: {\"model\":\"fopdt\",\"K\",\"tau\",\"Td\",\"y0\",\"u0\",\"cost\",\"fit\",\"evaluations\"}\n"
    "  sopdt: {\"model\":\"sopdt\",\"K\",\"wn\",\"zeta\",\"Td\",\"y0\",\"u0\",\"tau1\",\"tau2\",\n"
    "          \"a\",\"b\",\"cost\",\"fit\",\"evaluations\"}\n"
    "    K      DC gain, output units per input unit\n"
    "    tau    time constant, s;  Td dead time, s\n"
    "    wn     natural frequency, rad/s;  zeta damping ratio\n"
    "    tau1, tau2  the real time constants, tau1 >= tau2, of\n"
    "           K e^(-Td s) / ((tau1 s + 1)(tau2 s + 1)); null when zeta < 1\n"
    "    a, b   the denominator s^2 + a s + b (paper form (2))\n"
    "    y0, u0 output and input operating point (y0 estimated with the model)\n"
    "    cost   the criterion at the model (mean square, output units^2); elms\n"
    "           and eiv: the mean square one-step prediction error\n"
    "    fit    100 (1 - |y - ysim| / |y - mean(y)|), percent; 100 is perfect\n"
    "    evaluations  cost evaluations used; elms and eiv: dead times scanned\n"
    "  Integrating process (sopdt with b = 0, Ki e^(-Td s) / (s (tau2 s + 1))):\n"
    "    \"K\":null, \"Ki\" (after \"K\"): integrating gain, output units per input\n"
    "    unit per second, \"wn\":0, \"zeta\":null, \"tau1\":null, \"tau2\" = 1/a.\n"
    "\n",
    "reduce: a FOPDT or SOPDT from a known detailed model\n"
    "  K prod_j (Zj s + 1) / prod_i (Ti s + 1) e^(-D s), printed as identify\n"
    "  prints that model kind, without y0, u0, cost, fit and evaluations.\n"
    "  --method skogestad|sung  Skogestad's half rule, or Sung et al.'s fit of\n"
    "                        the frequency response up to the phase crossover\n"
    "                        (required). A sopdt that Sung's fit cannot give is\n"
    "                        printed as its fopdt (\"model\":\"fopdt\")\n"
    "  --model fopdt|sopdt   the reduced model (required)\n"
    "  --gain K              DC gain (required)\n"
    "  --lags T1,T2,...      lag time constants, s, each > 0 (required)\n"
    "  --zeros Z1,Z2,...     zero time constants of (Z s + 1), s, each != 0;\n"
    "                        negative for a right-half-plane zero\n"
    "  --delay D             dead time of the detailed model, s (default 0)\n"
    "  --h H                 skogestad: period of the digital controller, s;\n"
    "                        h/2 is added to the dead time (default 0)\n"
    "  Example, the paper's system (17):\n"
    "    pdtfit reduce --method skogestad --model fopdt --gain 1 \\\n"
    "      --lags 2,1,0.4,0.2,0.05,0.05,0.05 --zeros -0.3,0.08\n"
    "\n",
    "Exit status: 0 model printed; 1 the data cannot be identified or the model\n"
    "not reduced (the library's reason is printed, e.g. the input never moves);\n"
    "2 bad usage or an unreadable or malformed file. Errors are one line on\n"
    "stderr starting \"pdtfit: \"; nothing is printed on stdout then.\n",
};

typedef enum method { METHOD_GA, METHOD_ELMS, METHOD_EIV } method_t;

typedef struct options {
    int have_model;
    pdt_model_kind_t model;
    method_t method;
    int have_td_max;
    double td_max;
    const char *ga_only; /* a GA option given, for the error with elms/eiv */
    pdt_cost_kind_t cost;
    uint64_t seed;
    int have_fs;
    double fs;
    int have_evaluations;
    uint32_t evaluations;
    int have_population;
    uint32_t population;
    int integer_delay;
    const char *file;
} options_t;

#if defined(__GNUC__)
#define NORETURN_PRINTF(f, a) __attribute__((noreturn, format(printf, f, a)))
#define NORETURN __attribute__((noreturn))
#else
#define NORETURN_PRINTF(f, a)
#define NORETURN
#endif

static void fail(int status, const char *fmt, ...) NORETURN_PRINTF(2, 3);
static void print_help(void) NORETURN;

static void fail(int status, const char *fmt, ...)
{
    va_list ap;
    fputs("pdtfit: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(status);
}

static void print_help(void)
{
    fputs(usage_line, stdout);
    pdt_ident_config_t def;
    pdt_ident_config_default(&def);
    for (size_t i = 0; i < sizeof help_text / sizeof help_text[0]; i++) {
        if (help_text[i]) {
            fputs(help_text[i], stdout);
            continue;
        }
        printf("  --evaluations N       cost evaluations in all, search and refinement\n"
               "                        (default %lu)\n"
               "  --population N        GA individuals, even, 4 .. %u (default %u for fopdt,\n"
               "                        %u for sopdt)\n",
               (unsigned long)def.max_evaluations, (unsigned)PDT_IDENT_MAX_POPULATION,
               (unsigned)PDT_IDENT_POPULATION_FOPDT, (unsigned)PDT_IDENT_POPULATION_SOPDT);
    }
    exit(fflush(stdout) == 0 && !ferror(stdout) ? 0 : EXIT_REFUSED);
}

/* Decimal digits only: strtoull alone would accept signs and blanks. */
static int parse_u64(const char *s, uint64_t *out)
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

static int parse_real(const char *s, double *out)
{
    char *stop;
    errno = 0;
    double v = strtod(s, &stop);
    if (stop == s || *stop != '\0' || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

static void parse_identify_args(int argc, char **argv, options_t *o)
{
    /* Help wins over any mistake elsewhere on the line. */
    for (int i = 0; i < argc && strcmp(argv[i], "--") != 0; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) print_help();
    int only_files = 0;
    for (int i = 0; i < argc; i++) {
        const char *arg = argv[i];
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (o->file)
                fail(EXIT_USAGE, "identify: one FILE only, got '%s' after '%s'", arg, o->file);
            o->file = arg;
            continue;
        }
        if (strcmp(arg, "--") == 0) {
            only_files = 1;
            continue;
        }
        /* --name VALUE or --name=VALUE */
        char name[32];
        const char *value = NULL;
        const char *eq = strchr(arg, '=');
        size_t name_len = eq ? (size_t)(eq - arg) : strlen(arg);
        if (name_len >= sizeof name || arg[1] != '-')
            fail(EXIT_USAGE, "identify: unknown option '%s' (see pdtfit --help)", arg);
        memcpy(name, arg, name_len);
        name[name_len] = '\0';
        if (strcmp(name, "--integer-delay") == 0) {
            if (eq) fail(EXIT_USAGE, "identify: --integer-delay takes no value");
            o->integer_delay = 1;
            continue;
        }
        static const char *const valued[] = {"--model", "--cost", "--seed", "--fs",
                                             "--evaluations", "--population", "--method",
                                             "--td-max"};
        const char *known = NULL;
        for (size_t k = 0; k < sizeof valued / sizeof valued[0]; k++)
            if (strcmp(name, valued[k]) == 0) known = valued[k];
        if (!known) fail(EXIT_USAGE, "identify: unknown option '%s' (see pdtfit --help)", name);
        if (eq) {
            value = eq + 1;
        } else {
            if (i + 1 >= argc) fail(EXIT_USAGE, "identify: %s needs a value", name);
            value = argv[++i];
        }

        if (strcmp(name, "--cost") == 0 || strcmp(name, "--seed") == 0 ||
            strcmp(name, "--evaluations") == 0 || strcmp(name, "--population") == 0)
            o->ga_only = known;
        if (strcmp(name, "--model") == 0) {
            if (strcmp(value, "fopdt") == 0)
                o->model = PDT_MODEL_FOPDT;
            else if (strcmp(value, "sopdt") == 0)
                o->model = PDT_MODEL_SOPDT;
            else
                fail(EXIT_USAGE, "identify: unknown model '%s' (fopdt or sopdt)", value);
            o->have_model = 1;
        } else if (strcmp(name, "--method") == 0) {
            if (strcmp(value, "ga") == 0)
                o->method = METHOD_GA;
            else if (strcmp(value, "elms") == 0)
                o->method = METHOD_ELMS;
            else if (strcmp(value, "eiv") == 0)
                o->method = METHOD_EIV;
            else
                fail(EXIT_USAGE, "identify: unknown method '%s' (ga, elms or eiv)", value);
        } else if (strcmp(name, "--td-max") == 0) {
            if (parse_real(value, &o->td_max) != 0 || !(o->td_max >= 0.0))
                fail(EXIT_USAGE, "identify: --td-max needs a dead time >= 0 s, got '%s'", value);
            o->have_td_max = 1;
        } else if (strcmp(name, "--cost") == 0) {
            if (strcmp(value, "prediction") == 0)
                o->cost = PDT_COST_PREDICTION;
            else if (strcmp(value, "simulation") == 0)
                o->cost = PDT_COST_SIMULATION;
            else if (strcmp(value, "frequency") == 0)
                o->cost = PDT_COST_FREQUENCY;
            else if (strcmp(value, "combined") == 0)
                o->cost = PDT_COST_COMBINED;
            else
                fail(EXIT_USAGE,
                     "identify: unknown cost '%s' (prediction, simulation, frequency or combined)",
                     value);
        } else if (strcmp(name, "--seed") == 0) {
            if (parse_u64(value, &o->seed) != 0)
                fail(EXIT_USAGE, "identify: --seed needs a whole number >= 0, got '%s'", value);
        } else if (strcmp(name, "--fs") == 0) {
            if (parse_real(value, &o->fs) != 0 || !(o->fs > 0.0))
                fail(EXIT_USAGE, "identify: --fs needs a sampling frequency > 0 Hz, got '%s'",
                     value);
            o->have_fs = 1;
        } else if (strcmp(name, "--evaluations") == 0) {
            uint64_t v;
            if (parse_u64(value, &v) != 0 || v == 0 || v > UINT32_MAX)
                fail(EXIT_USAGE, "identify: --evaluations needs a whole number >= 1, got '%s'",
                     value);
            o->evaluations = (uint32_t)v;
            o->have_evaluations = 1;
        } else {
            uint64_t v;
            if (parse_u64(value, &v) != 0 || v < 4 || v > PDT_IDENT_MAX_POPULATION || v % 2 != 0)
                fail(EXIT_USAGE, "identify: --population needs an even number from 4 to %u, got '%s'",
                     (unsigned)PDT_IDENT_MAX_POPULATION, value);
            o->population = (uint32_t)v;
            o->have_population = 1;
        }
    }
    if (!o->have_model) fail(EXIT_USAGE, "identify: --model fopdt|sopdt is required");
    if (o->method != METHOD_GA && o->ga_only)
        fail(EXIT_USAGE, "identify: %s is an option of --method ga only", o->ga_only);
    if (o->method == METHOD_GA && o->have_td_max && !(o->td_max > 0.0))
        fail(EXIT_USAGE, "identify: --td-max must be > 0 s with --method ga");
    if (!o->file) fail(EXIT_USAGE, "identify: missing FILE (a CSV file, or - for stdin)");
}

/* The sampling period: from t (uniform within TS_TOLERANCE), from --fs, or
 * both when they agree. */
static double sampling_period(const csv_table_t *tab, const options_t *o, const char *name)
{
    if (!tab->t) {
        if (!o->have_fs) fail(EXIT_USAGE, "%s: no t column: give the sampling frequency with --fs", name);
        return 1.0 / o->fs;
    }
    const double *t = tab->t;
    size_t n = tab->rows;
    /* Data rows are lines 2, 3, ... (blank lines cannot sit between rows). */
    for (size_t k = 1; k < n; k++)
        if (!(t[k] > t[k - 1]))
            fail(EXIT_USAGE, "%s:%zu: t does not increase (%.9g after %.9g)", name, k + 2, t[k],
                 t[k - 1]);
    double Ts = (t[n - 1] - t[0]) / (double)(n - 1);
    if (!(Ts > 0.0) || !isfinite(Ts))
        fail(EXIT_USAGE, "%s: t does not give a usable sampling period", name);
    for (size_t k = 0; k < n; k++) {
        double expect = t[0] + (double)k * Ts;
        if (fabs(t[k] - expect) > TS_TOLERANCE * Ts)
            fail(EXIT_USAGE,
                 "%s:%zu: t is not uniformly sampled: %.9g, expected %.9g (Ts = %.9g s, "
                 "tolerance 1%% of Ts)",
                 name, k + 2, t[k], expect, Ts);
    }
    if (o->have_fs) {
        double Ts_fs = 1.0 / o->fs;
        if (fabs(Ts_fs - Ts) > TS_TOLERANCE * Ts)
            fail(EXIT_USAGE, "%s: --fs %.9g Hz (Ts = %.9g s) disagrees with the t column (Ts = %.9g s)",
                 name, o->fs, Ts_fs, Ts);
        /* Timestamps jitter; the nominal rate the user gave is exact. */
        return Ts_fs;
    }
    return Ts;
}

static void json_num(double v)
{
    if (isfinite(v))
        printf("%.9g", v);
    else
        fputs("null", stdout);
}

static void json_key(const char *key, double v)
{
    printf(",\"%s\":", key);
    json_num(v);
}

/* One model as JSON. r NULL (pdtfit reduce): the model's keys only, no
 * operating point, cost, fit or evaluations. */
static void print_model(const pdt_model_t *model, const pdt_ident_result_t *r)
{
    if (model->kind == PDT_MODEL_FOPDT) {
        const pdt_fopdt_t *m = &model->p.fopdt;
        fputs("{\"model\":\"fopdt\"", stdout);
        json_key("K", (double)m->K);
        json_key("tau", (double)m->tau);
        json_key("Td", (double)m->Td);
        if (r) {
            json_key("y0", (double)r->y0);
            json_key("u0", (double)r->u0);
        }
    } else {
        const pdt_sopdt_t *m = &model->p.sopdt;
        pdt_sopdt_natural_t nat;
        pdt_sopdt_tc_t tc;
        pdt_sopdt_integ_t integ;
        fputs("{\"model\":\"sopdt\"", stdout);
        if (pdt_sopdt_to_natural(m, &nat) == PDT_OK) {
            double tau1 = (double)NAN, tau2 = (double)NAN;
            if (pdt_sopdt_to_tc(m, &tc) == PDT_OK && !tc.complex) {
                tau1 = (double)tc.T1;
                tau2 = (double)tc.T2;
            }
            json_key("K", (double)nat.K);
            json_key("wn", (double)nat.wn);
            json_key("zeta", (double)nat.zeta);
            json_key("Td", (double)m->Td);
            if (r) {
                json_key("y0", (double)r->y0);
                json_key("u0", (double)r->u0);
            }
            json_key("tau1", tau1);
            json_key("tau2", tau2);
        } else if (pdt_sopdt_to_integ(m, &integ) == PDT_OK) {
            json_key("K", (double)NAN);
            json_key("Ki", (double)integ.Ki);
            json_key("wn", 0.0);
            json_key("zeta", (double)NAN);
            json_key("Td", (double)m->Td);
            if (r) {
                json_key("y0", (double)r->y0);
                json_key("u0", (double)r->u0);
            }
            json_key("tau1", (double)NAN);
            json_key("tau2", (double)integ.T);
        } else {
            /* Not reachable for a model the library returned; kept so the
             * output is still complete if it ever is. */
            json_key("K", (double)NAN);
            json_key("wn", (double)NAN);
            json_key("zeta", (double)NAN);
            json_key("Td", (double)m->Td);
            if (r) {
                json_key("y0", (double)r->y0);
                json_key("u0", (double)r->u0);
            }
            json_key("tau1", (double)NAN);
            json_key("tau2", (double)NAN);
        }
        json_key("a", (double)m->a);
        json_key("b", (double)m->b);
    }
    if (r) {
        json_key("cost", (double)r->cost);
        json_key("fit", (double)r->fit);
        printf(",\"evaluations\":%lu", (unsigned long)r->evaluations);
    }
    fputs("}\n", stdout);
}

static void print_result(const pdt_ident_result_t *r) { print_model(&r->model, r); }

static const char *status_hint(pdt_status_t st)
{
    switch (st) {
    case PDT_ERR_NO_EXCITATION:
        return " (u or y does not move: record a step or other change of the input)";
    case PDT_ERR_TOO_SHORT:
        return " (the record is too short for the dead-time range: record longer)";
    case PDT_ERR_LENGTH:
        return " (the record is too long for the frequency cost: decimate it)";
    case PDT_ERR_ARG:
        return " (a setting is out of range, e.g. --evaluations too small, or the sampling "
               "period is unusable)";
    case PDT_ERR_NO_FORM:
        return " (no dead time in the scan gave a stable model of this order: try the other "
               "model or --method ga)";
    default:
        return "";
    }
}

/* The fit of a model as pdt_ident reports it: the continuous model
 * discretised exactly and run from rest on u - u0, plus y0, against y.
 * NaN when it cannot be simulated. */
static double model_fit(const pdt_model_t *m, double Ts, const pdt_real_t *u, const pdt_real_t *y,
                        size_t n, pdt_real_t u0, pdt_real_t y0)
{
    pdt_cost_config_t cc;
    pdt_cost_config_default(&cc);
    cc.Ts = (pdt_real_t)Ts;
    cc.u0 = u0;
    cc.y0 = y0;
    cc.delay_max = 0;
    cc.whole_record = true;
    cc.use_frequency = false;
    cc.kind = PDT_COST_SIMULATION;
    pdt_cost_t cost;
    pdt_dmodel_t d;
    pdt_real_t *ysim = malloc(n * sizeof *ysim);
    if (!ysim) fail(EXIT_REFUSED, "out of memory");
    double fit = (double)NAN;
    if (pdt_cost_init(&cost, &cc, u, y, n, NULL, 0) == PDT_OK &&
        pdt_discretize(m, (pdt_real_t)Ts, &d) == PDT_OK &&
        pdt_cost_simulate(&cost, &d, ysim) == PDT_OK) {
        double mean = 0.0, e2 = 0.0, v2 = 0.0;
        for (size_t k = 0; k < n; k++) mean += (double)y[k];
        mean /= (double)n;
        for (size_t k = 0; k < n; k++) {
            double e = (double)y[k] - (double)ysim[k], v = (double)y[k] - mean;
            e2 += e * e;
            v2 += v * v;
        }
        if (v2 > 0.0) fit = 100.0 * (1.0 - sqrt(e2 / v2));
    }
    free(ysim);
    return fit;
}

/* identify --method elms|eiv: the least-squares delay scan, printed in the
 * same form as the GA's result. */
static void identify_ls(const options_t *o, double Ts, const pdt_real_t *u, const pdt_real_t *y,
                        size_t n)
{
    pdt_ls_config_t cfg;
    pdt_ls_config_default(&cfg);
    cfg.model = o->model;
    cfg.method = o->method == METHOD_EIV ? PDT_LS_EIV : PDT_LS_ELMS;
    cfg.Ts = (pdt_real_t)Ts;
    if (o->have_td_max) {
        /* A bound at or past the record's end is the library's to refuse
         * (too short); the clamp only keeps the conversion defined. */
        double l = floor(o->td_max / Ts + 1e-9);
        cfg.delay_max = l < (double)n ? (size_t)l : n;
    }
    size_t delay_max = o->have_td_max ? cfg.delay_max : n / 4u;
    pdt_ls_t *ctx = malloc(sizeof *ctx);
    if (!ctx) fail(EXIT_REFUSED, "out of memory");
    pdt_ls_result_t r;
    pdt_status_t st = pdt_ls_identify(ctx, &cfg, u, y, n, &r);
    free(ctx);
    if (st != PDT_OK)
        fail(EXIT_REFUSED, "cannot identify: %s%s", pdt_status_str(st), status_hint(st));

    pdt_ident_result_t res;
    memset(&res, 0, sizeof res);
    res.model = r.model;
    res.u0 = r.u0;
    res.y0 = r.y0;
    res.cost = r.cost;
    res.fit = (pdt_real_t)model_fit(&r.model, Ts, u, y, n, r.u0, r.y0);
    res.evaluations = (uint32_t)(delay_max - cfg.delay_min + 1u);
    print_result(&res);
}

static int cmd_identify(int argc, char **argv)
{
    options_t o;
    memset(&o, 0, sizeof o);
    o.cost = PDT_COST_SIMULATION;
    o.seed = 1;
    parse_identify_args(argc, argv, &o);

    const int from_stdin = strcmp(o.file, "-") == 0;
    const char *name = from_stdin ? "stdin" : o.file;
    FILE *in = from_stdin ? stdin : fopen(o.file, "rb");
    if (!in) fail(EXIT_USAGE, "cannot open %s: %s", o.file, strerror(errno));

    const double max_abs = sizeof(pdt_real_t) == sizeof(float) ? (double)FLT_MAX : DBL_MAX;
    csv_table_t tab;
    char err[512];
    int rc = csv_read_tuy(in, name, max_abs, &tab, err, sizeof err);
    if (!from_stdin) fclose(in);
    if (rc != 0) fail(EXIT_USAGE, "%s", err);
    if (tab.rows < PDT_MIN_SAMPLES)
        fail(EXIT_USAGE, "%s: %zu data row%s, at least %u needed", name, tab.rows,
             tab.rows == 1 ? "" : "s", (unsigned)PDT_MIN_SAMPLES);
    const double Ts = sampling_period(&tab, &o, name);
    if (!(Ts <= max_abs) || !((double)(pdt_real_t)Ts > 0.0))
        fail(EXIT_USAGE, "%s: sampling period %.9g s is out of range", name, Ts);

    const size_t n = tab.rows;
    pdt_real_t *u = malloc(n * sizeof *u);
    pdt_real_t *y = malloc(n * sizeof *y);
    if (!u || !y) fail(EXIT_REFUSED, "out of memory");
    for (size_t k = 0; k < n; k++) {
        u[k] = (pdt_real_t)tab.u[k];
        y[k] = (pdt_real_t)tab.y[k];
    }
    csv_table_free(&tab);

    if (o.method != METHOD_GA) {
        identify_ls(&o, Ts, u, y, n);
        free(y);
        free(u);
        if (fflush(stdout) != 0 || ferror(stdout)) fail(EXIT_REFUSED, "cannot write the result");
        return 0;
    }

    pdt_ident_t *ctx = malloc(sizeof *ctx);
    if (!ctx) fail(EXIT_REFUSED, "out of memory");
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.model = o.model;
    cfg.Ts = (pdt_real_t)Ts;
    cfg.cost = o.cost;
    cfg.seed = o.seed;
    if (o.integer_delay) cfg.delay_mode = PDT_DELAY_INTEGER;
    if (o.have_evaluations) cfg.max_evaluations = o.evaluations;
    if (o.have_population) cfg.population = o.population;
    if (o.have_td_max) cfg.Td_max = (pdt_real_t)o.td_max;

    /* A size of 0 means the configuration is refused; pdt_identify then
     * says why, so it is still called. */
    size_t work_len = pdt_ident_workspace_size(&cfg, n);
    void *work = NULL;
    if (work_len > 0) {
        work = malloc(work_len);
        if (!work) fail(EXIT_REFUSED, "out of memory (%zu bytes of workspace)", work_len);
    }
    const pdt_ident_data_t data = {u, y, n};
    pdt_ident_result_t res;
    pdt_status_t st = pdt_identify(ctx, &cfg, &data, work, work_len, &res);
    if (st != PDT_OK)
        fail(EXIT_REFUSED, "cannot identify: %s%s", pdt_status_str(st), status_hint(st));

    print_result(&res);
    free(work);
    free(ctx);
    free(y);
    free(u);
    if (fflush(stdout) != 0 || ferror(stdout)) fail(EXIT_REFUSED, "cannot write the result");
    return 0;
}

#define REDUCE_MAX_LIST 64

/* A comma-separated list of finite numbers: count, or -1. */
static int parse_list(const char *s, double *out, int max)
{
    char buf[32];
    int count = 0;
    for (;;) {
        const char *comma = strchr(s, ',');
        size_t len = comma ? (size_t)(comma - s) : strlen(s);
        if (len == 0 || len >= sizeof buf || count >= max) return -1;
        memcpy(buf, s, len);
        buf[len] = '\0';
        if (parse_real(buf, &out[count]) != 0) return -1;
        count++;
        if (!comma) return count;
        s = comma + 1;
    }
}

static int cmd_reduce(int argc, char **argv)
{
    for (int i = 0; i < argc; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) print_help();
    int method = -1; /* 0 skogestad, 1 sung */
    int have_model = 0, have_gain = 0, have_h = 0;
    pdt_model_kind_t model = PDT_MODEL_FOPDT;
    double gain = 0.0, delay = 0.0, h = 0.0;
    double lags_d[REDUCE_MAX_LIST], zeros_d[REDUCE_MAX_LIST];
    int n_lags = -1, n_zeros = 0;
    for (int i = 0; i < argc; i++) {
        const char *arg = argv[i];
        if (arg[0] != '-' || arg[1] != '-')
            fail(EXIT_USAGE, "reduce: unexpected argument '%s' (reduce reads no file)", arg);
        char name[32];
        const char *eq = strchr(arg, '=');
        size_t name_len = eq ? (size_t)(eq - arg) : strlen(arg);
        if (name_len >= sizeof name)
            fail(EXIT_USAGE, "reduce: unknown option '%s' (see pdtfit --help)", arg);
        memcpy(name, arg, name_len);
        name[name_len] = '\0';
        static const char *const valued[] = {"--method", "--model", "--gain", "--lags",
                                             "--zeros", "--delay", "--h"};
        int known = 0;
        for (size_t k = 0; k < sizeof valued / sizeof valued[0]; k++)
            if (strcmp(name, valued[k]) == 0) known = 1;
        if (!known) fail(EXIT_USAGE, "reduce: unknown option '%s' (see pdtfit --help)", name);
        const char *value;
        if (eq) {
            value = eq + 1;
        } else {
            if (i + 1 >= argc) fail(EXIT_USAGE, "reduce: %s needs a value", name);
            value = argv[++i];
        }
        if (strcmp(name, "--method") == 0) {
            if (strcmp(value, "skogestad") == 0)
                method = 0;
            else if (strcmp(value, "sung") == 0)
                method = 1;
            else
                fail(EXIT_USAGE, "reduce: unknown method '%s' (skogestad or sung)", value);
        } else if (strcmp(name, "--model") == 0) {
            if (strcmp(value, "fopdt") == 0)
                model = PDT_MODEL_FOPDT;
            else if (strcmp(value, "sopdt") == 0)
                model = PDT_MODEL_SOPDT;
            else
                fail(EXIT_USAGE, "reduce: unknown model '%s' (fopdt or sopdt)", value);
            have_model = 1;
        } else if (strcmp(name, "--gain") == 0) {
            if (parse_real(value, &gain) != 0)
                fail(EXIT_USAGE, "reduce: --gain needs a finite number, got '%s'", value);
            have_gain = 1;
        } else if (strcmp(name, "--lags") == 0) {
            n_lags = parse_list(value, lags_d, REDUCE_MAX_LIST);
            if (n_lags < 0)
                fail(EXIT_USAGE, "reduce: --lags needs 1 to %d numbers separated by commas, "
                     "got '%s'", REDUCE_MAX_LIST, value);
            for (int k = 0; k < n_lags; k++)
                if (!(lags_d[k] > 0.0))
                    fail(EXIT_USAGE, "reduce: --lags: every time constant must be > 0, got %.9g",
                         lags_d[k]);
        } else if (strcmp(name, "--zeros") == 0) {
            n_zeros = parse_list(value, zeros_d, REDUCE_MAX_LIST);
            if (n_zeros < 0)
                fail(EXIT_USAGE, "reduce: --zeros needs 1 to %d numbers separated by commas, "
                     "got '%s'", REDUCE_MAX_LIST, value);
            for (int k = 0; k < n_zeros; k++)
                if (zeros_d[k] == 0.0)
                    fail(EXIT_USAGE, "reduce: --zeros: a zero time constant cannot be 0");
        } else if (strcmp(name, "--delay") == 0) {
            if (parse_real(value, &delay) != 0 || !(delay >= 0.0))
                fail(EXIT_USAGE, "reduce: --delay needs a dead time >= 0 s, got '%s'", value);
        } else {
            if (parse_real(value, &h) != 0 || !(h >= 0.0))
                fail(EXIT_USAGE, "reduce: --h needs a controller period >= 0 s, got '%s'", value);
            have_h = 1;
        }
    }
    if (method < 0) fail(EXIT_USAGE, "reduce: --method skogestad|sung is required");
    if (!have_model) fail(EXIT_USAGE, "reduce: --model fopdt|sopdt is required");
    if (!have_gain) fail(EXIT_USAGE, "reduce: --gain K is required");
    if (n_lags < 0) fail(EXIT_USAGE, "reduce: --lags T1,T2,... is required");
    if (have_h && method == 1) fail(EXIT_USAGE, "reduce: --h is an option of --method skogestad only");

    pdt_real_t lags[REDUCE_MAX_LIST], zeros[REDUCE_MAX_LIST];
    for (int k = 0; k < n_lags; k++) lags[k] = (pdt_real_t)lags_d[k];
    for (int k = 0; k < n_zeros; k++) zeros[k] = (pdt_real_t)zeros_d[k];
    const pdt_reduce_plant_t plant = {(pdt_real_t)gain, lags, (size_t)n_lags,
                                      n_zeros > 0 ? zeros : NULL, (size_t)n_zeros,
                                      (pdt_real_t)delay};
    pdt_reduce_config_t cfg;
    pdt_reduce_config_default(&cfg);
    cfg.model = model;
    cfg.h = (pdt_real_t)h;
    pdt_model_t out;
    pdt_status_t st = method == 0 ? pdt_reduce_half_rule(&plant, &cfg, &out, NULL)
                                  : pdt_reduce_sung(&plant, &cfg, &out, NULL);
    if (st != PDT_OK) {
        const char *hint = "";
        if (st == PDT_ERR_NO_FORM)
            hint = method == 0 ? " (a zero has no lag to cancel against, or fewer lags than "
                                 "the model's order)"
                               : " (the phase of the model never reaches -180 degrees, or "
                                 "its gain is 0)";
        else if (st == PDT_ERR_LENGTH)
            hint = " (too many lags for the half rule)";
        else if (st == PDT_ERR_ARG)
            hint = " (a value is out of the real type's range)";
        fail(EXIT_REFUSED, "cannot reduce: %s%s", pdt_status_str(st), hint);
    }
    print_model(&out, NULL);
    if (fflush(stdout) != 0 || ferror(stdout)) fail(EXIT_REFUSED, "cannot write the result");
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs("pdtfit: missing command (usage: pdtfit identify --model fopdt|sopdt FILE.csv; "
              "see pdtfit --help)\n",
              stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0)
        print_help();
    if (strcmp(cmd, "--version") == 0) {
        printf("pdtfit %s (pdt_real_t = %s)\n", PDT_VERSION_STRING,
               sizeof(pdt_real_t) == sizeof(float) ? "float" : "double");
        return fflush(stdout) == 0 ? 0 : EXIT_REFUSED;
    }
    if (strcmp(cmd, "identify") == 0) return cmd_identify(argc - 2, argv + 2);
    if (strcmp(cmd, "reduce") == 0) return cmd_reduce(argc - 2, argv + 2);
    fail(EXIT_USAGE, "unknown command '%s' (see pdtfit --help)", cmd);
    return EXIT_USAGE;
}
