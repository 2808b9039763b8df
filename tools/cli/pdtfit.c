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
#include "plant_sim.h"
#include "pdt/pdt.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_ls.h"
#include "pdt/pdt_reduce.h"

#define M_PI_VALUE 3.14159265358979323846

#define EXIT_REFUSED 1
#define EXIT_USAGE 2

/* Relative tolerance on the sampling period: t against a uniform grid, and
 * --fs against t. */
#define TS_TOLERANCE 0.01

static const char usage_line[] =
    "usage: pdtfit identify --model fopdt|sopdt [--method ga|elms|eiv] [options] FILE.csv\n"
    "       pdtfit reduce --method skogestad|sung --model fopdt|sopdt --gain K\n"
    "                     --lags T1,T2,... [--zeros Z1,...] [--delay D] [--h H]\n"
    "       pdtfit tune --rule simc|imc|amigo|zn [--form pi|pid] --model fopdt|sopdt\n"
    "                   --K K --Td D (--tau T | --wn W --zeta Z | --tau1 T1 --tau2 T2)\n"
    "       pdtfit tune --rule zn [--form pi|pid] --Ku KU --Pu PU\n"
    "       pdtfit autotune-sim --plant-gain K --plant-lags T1,... [options]\n"
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
    "                        rest (u back at u[0], y settled) and refuse one that\n"
    "                        clearly does not.\n"
    "  --weight KIND         frequency weighting of frequency and combined:\n"
    "                          auto     (default) control for fopdt with combined,\n"
    "                                   else uniform\n"
    "                          control  the band from 0 to half the phase crossover\n"
    "                                   of the model the simulation cost finds\n"
    "                                   first: where a controller needs the model.\n"
    "                                   The output adds \"f_band\" (Hz)\n"
    "                          uniform  every frequency bin alike (the paper's W = 1)\n"
    "                          band     the bins in --band F_LO:F_HI only\n"
    "  --band F_LO:F_HI      the band of --weight band, Hz, 0 <= F_LO <= F_HI\n"
    "  --phi-t X, --phi-f X  weights of the time and frequency parts of combined,\n"
    "                        >= 0 (default 1 and 1)\n"
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
    "tune: PI/PID gains of a known model by a published rule, with the\n"
    "  robustness of the loop they make (pdt_tune.h, docs/tuning.md)\n"
    "  --rule simc|imc|amigo|zn  the rule (required)\n"
    "  --form pi|pid         the controller (default pi)\n"
    "  --model fopdt|sopdt   with --K and --Td, and --tau (fopdt), or --wn and\n"
    "                        --zeta, or --tau1 and --tau2 (sopdt)\n"
    "  --Ku KU --Pu PU       zn only: ultimate gain and period (e.g. from a relay)\n"
    "                        instead of a model; with a model too, the figures\n"
    "                        are those of these gains on that model\n"
    "  --tau-c X             simc: closed-loop time constant, s (default Td)\n"
    "  --lambda X            imc: closed-loop time constant, s (default\n"
    "                        max(tau, 3 Td))\n"
    "  --ms-max X            refuse gains whose Ms exceeds X (default 2; 0: none)\n"
    "  --deriv-filter N      derivative filter Tf = tauD / N (default 10; 0: none)\n"
    "  Prints {\"rule\",\"form\",\"Kc\",\"tauI\",\"tauD\",\"Tf\" (ideal form),\"Ms\",\n"
    "  \"gain_margin\",\"phase_margin_deg\",\"w_ms\",\"w_pc\",\"w_gc\" (rad/s),\n"
    "  \"series\" ({\"Kc\",\"tauI\",\"tauD\",\"Tf\"} or null),\"stated_in\", and\n"
    "  \"tau_c\" (simc) or \"lambda\" (imc)}. null: infinite or absent.\n"
    "\n",
    "autotune-sim: the on-device autotune (pdt_autotune) run scan by scan on a\n"
    "  simulated plant K prod (Zj s + 1) / prod (Ti s + 1) e^(-D s)\n"
    "  --plant-gain K, --plant-lags T1,..., --plant-zeros Z1,..., --plant-delay D\n"
    "                        the plant, as for reduce (gain and lags required)\n"
    "  --experiment KIND     step|pulse|chirp|prbs|relay (default prbs)\n"
    "  --amplitude A         step/pulse change, chirp/prbs half swing, relay d\n"
    "                        (default 1)\n"
    "  --scan-period S       default (sum of lags + D) / 200\n"
    "  --decimation N        scans per identification sample (default 4)\n"
    "  --capacity N          samples recorded (default: settle + the experiment\n"
    "                        + a settling time 4 sum(lags) + D)\n"
    "  --model fopdt|sopdt   identified model (default fopdt); --evaluations N\n"
    "  --rule, --form, --tau-c, --lambda, --ms-max, --deriv-filter  as for tune\n"
    "  --noise STD, --seed N Gaussian noise on pv; seed of noise and search\n"
    "  --u0 U, --y0 Y        operating point (default 0, 0)\n"
    "  --setpoint SP         relay set-point (default y0)\n"
    "  --pv-min, --pv-max, --u-min, --u-max  safety limits (default none)\n"
    "  --trace FILE          also write t,u,pv of every scan as CSV\n"
    "  Prints {\"status\",\"reason\",[\"failed_in\"],\"scan_period\",\"decimation\",\n"
    "  \"capacity\",\"samples\",\"scans\",\"experiment\",\"phases\",\"ident\" (as\n"
    "  identify),\"tune\" (as tune),[\"relay\"]}; printed also when the autotune\n"
    "  aborts or refuses, with exit status 1 and the reason on stderr.\n"
    "\n",
    "Exit status: 0 model printed; 1 the data cannot be identified, the model\n"
    "not reduced, gains refused or the autotune aborted (the library's reason is\n"
    "printed, e.g. the input never moves); 2 bad usage or an unreadable or\n"
    "malformed file. Errors are one line on stderr starting \"pdtfit: \"; nothing\n"
    "is printed on stdout then (except autotune-sim's JSON).\n",
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
    int have_weight;
    int have_band;
    pdt_weight_kind_t weight;
    double f_lo, f_hi;
    int have_phi_t, have_phi_f;
    double phi_t, phi_f;
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

/* Whether a finite double stays finite as pdt_real_t (float by default). */
static int real_fits(double v)
{
    return isfinite((double)(pdt_real_t)v);
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
                                             "--td-max", "--weight", "--band", "--phi-t",
                                             "--phi-f"};
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
            strcmp(name, "--evaluations") == 0 || strcmp(name, "--population") == 0 ||
            strcmp(name, "--weight") == 0 || strcmp(name, "--band") == 0 ||
            strcmp(name, "--phi-t") == 0 || strcmp(name, "--phi-f") == 0)
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
        } else if (strcmp(name, "--weight") == 0) {
            if (strcmp(value, "auto") == 0)
                o->weight = PDT_WEIGHT_AUTO;
            else if (strcmp(value, "control") == 0)
                o->weight = PDT_WEIGHT_CONTROL;
            else if (strcmp(value, "uniform") == 0)
                o->weight = PDT_WEIGHT_UNIFORM;
            else if (strcmp(value, "band") == 0)
                o->weight = PDT_WEIGHT_BAND;
            else
                fail(EXIT_USAGE,
                     "identify: unknown weight '%s' (auto, control, uniform or band)", value);
            o->have_weight = 1;
        } else if (strcmp(name, "--band") == 0) {
            char lo[64];
            const char *colon = strchr(value, ':');
            size_t len = colon ? (size_t)(colon - value) : 0;
            if (!colon || len >= sizeof lo)
                fail(EXIT_USAGE, "identify: --band needs F_LO:F_HI in Hz, got '%s'", value);
            memcpy(lo, value, len);
            lo[len] = '\0';
            if (parse_real(lo, &o->f_lo) != 0 || parse_real(colon + 1, &o->f_hi) != 0 ||
                !(o->f_lo >= 0.0) || !(o->f_hi >= o->f_lo) || !real_fits(o->f_hi))
                fail(EXIT_USAGE,
                     "identify: --band needs F_LO:F_HI in Hz, 0 <= F_LO <= F_HI, got '%s'", value);
            o->have_band = 1;
        } else if (strcmp(name, "--phi-t") == 0 || strcmp(name, "--phi-f") == 0) {
            double v;
            if (parse_real(value, &v) != 0 || !(v >= 0.0) || !real_fits(v))
                fail(EXIT_USAGE, "identify: %s needs a weight >= 0, got '%s'", name, value);
            if (name[6] == 't') {
                o->phi_t = v;
                o->have_phi_t = 1;
            } else {
                o->phi_f = v;
                o->have_phi_f = 1;
            }
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
    if (o->have_weight && o->weight == PDT_WEIGHT_BAND && !o->have_band)
        fail(EXIT_USAGE, "identify: --weight band needs --band F_LO:F_HI");
    if (o->have_band && !(o->have_weight && o->weight == PDT_WEIGHT_BAND))
        fail(EXIT_USAGE, "identify: --band goes with --weight band");
    if (o->have_phi_t && o->have_phi_f && o->phi_t == 0.0 && o->phi_f == 0.0)
        fail(EXIT_USAGE, "identify: --phi-t and --phi-f cannot both be 0");
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

/* One model as a JSON object (no line end). r NULL (pdtfit reduce): the
 * model's keys only, no operating point, cost, fit or evaluations. */
static void print_model_object(const pdt_model_t *model, const pdt_ident_result_t *r)
{
    if (model->kind == PDT_MODEL_FOPDT) {
        const pdt_model_fopdt_t *m = &model->p.fopdt;
        fputs("{\"model\":\"fopdt\"", stdout);
        json_key("K", (double)m->K);
        json_key("tau", (double)m->tau);
        json_key("Td", (double)m->Td);
        if (r) {
            json_key("y0", (double)r->y0);
            json_key("u0", (double)r->u0);
        }
    } else {
        const pdt_model_sopdt_t *m = &model->p.sopdt;
        pdt_model_natural_t nat;
        pdt_model_tc_t tc;
        pdt_model_integ_t integ;
        fputs("{\"model\":\"sopdt\"", stdout);
        if (pdt_model_sopdt_to_natural(m, &nat) == PDT_OK) {
            double tau1 = (double)NAN, tau2 = (double)NAN;
            if (pdt_model_sopdt_to_tc(m, &tc) == PDT_OK && !tc.complex) {
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
        } else if (pdt_model_sopdt_to_integ(m, &integ) == PDT_OK) {
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
        if (r->f_band > (pdt_real_t)0) json_key("f_band", (double)r->f_band);
    }
    fputc('}', stdout);
}

static void print_model(const pdt_model_t *model, const pdt_ident_result_t *r)
{
    print_model_object(model, r);
    fputc('\n', stdout);
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
        return " (a setting is out of range, e.g. --evaluations too small, a --band outside "
               "0 .. fs/2, or the sampling period is unusable)";
    case PDT_ERR_NO_FORM:
        return " (no dead time in the scan gave a stable model of this order: try the other "
               "model or --method ga)";
    case PDT_ERR_NOT_AT_REST:
        return " (the frequency and combined costs need u back at its start and y settled at "
               "the end of the record: use --cost simulation)";
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
    pdt_discrete_t d;
    size_t wlen = pdt_cost_workspace_size(&cc, n);
    pdt_real_t *ysim = malloc(n * sizeof *ysim + wlen);
    if (!ysim) fail(EXIT_REFUSED, "out of memory");
    double fit = (double)NAN;
    if (pdt_cost_init(&cost, &cc, u, y, n, ysim + n, wlen) == PDT_OK &&
        pdt_discrete_init(m, (pdt_real_t)Ts, &d) == PDT_OK &&
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
    if (o.have_weight) cfg.weight = o.weight;
    cfg.f_lo = (pdt_real_t)o.f_lo;
    cfg.f_hi = (pdt_real_t)o.f_hi;
    if (o.have_phi_t) cfg.phi_t = (pdt_real_t)o.phi_t;
    if (o.have_phi_f) cfg.phi_f = (pdt_real_t)o.phi_f;

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

/* ------------------------------------------------------------------ tune */

/* The enum's name without PDT_ / PDT_ERR_, for scripts ("POOR_FIT"). */
static const char *status_name(pdt_status_t st)
{
    switch (st) {
    case PDT_RUNNING: return "RUNNING";
    case PDT_OK: return "OK";
    case PDT_ERR_ARG: return "ARG";
    case PDT_ERR_LENGTH: return "LENGTH";
    case PDT_ERR_NOMEM: return "NOMEM";
    case PDT_ERR_NONFINITE: return "NONFINITE";
    case PDT_ERR_TOO_SHORT: return "TOO_SHORT";
    case PDT_ERR_BOUNDS: return "BOUNDS";
    case PDT_ERR_NO_FORM: return "NO_FORM";
    case PDT_ERR_NO_EXCITATION: return "NO_EXCITATION";
    case PDT_ERR_STATE: return "STATE";
    case PDT_ERR_PV_LIMIT: return "PV_LIMIT";
    case PDT_ERR_OUTPUT_LIMIT: return "OUTPUT_LIMIT";
    case PDT_ERR_TIMEOUT: return "TIMEOUT";
    case PDT_ERR_SETPOINT: return "SETPOINT";
    case PDT_ERR_POOR_FIT: return "POOR_FIT";
    case PDT_ERR_UNSTABLE: return "UNSTABLE";
    case PDT_ERR_ABORTED: return "ABORTED";
    case PDT_ERR_NOT_AT_REST: return "NOT_AT_REST";
    default: return "UNKNOWN";
    }
}

static const char *const rule_names[] = {"simc", "imc", "amigo", "zn"};
static const char *const form_names[] = {"pi", "pid"};

/* The options of the tuning rule, shared by tune and autotune-sim. */
typedef struct tune_opts {
    pdt_tune_rule_t rule;
    pdt_tune_form_t form;
    int have_tau_c, have_lambda, have_ms_max, have_filter;
    double tau_c, lambda, ms_max, deriv_filter;
} tune_opts_t;

/* Splits argv[*i] into an option name and its value (next argument or
 * after '='); fails on anything not listed in valued. */
static void take_option(int argc, char **argv, int *i, const char *cmd,
                        const char *const *valued, size_t n_valued, char name[32],
                        const char **value)
{
    const char *arg = argv[*i];
    if (arg[0] != '-' || arg[1] != '-')
        fail(EXIT_USAGE, "%s: unexpected argument '%s' (%s reads no file)", cmd, arg, cmd);
    const char *eq = strchr(arg, '=');
    size_t name_len = eq ? (size_t)(eq - arg) : strlen(arg);
    if (name_len >= 32) fail(EXIT_USAGE, "%s: unknown option '%s' (see pdtfit --help)", cmd, arg);
    memcpy(name, arg, name_len);
    name[name_len] = '\0';
    int known = 0;
    for (size_t k = 0; k < n_valued; k++)
        if (strcmp(name, valued[k]) == 0) known = 1;
    if (!known) fail(EXIT_USAGE, "%s: unknown option '%s' (see pdtfit --help)", cmd, name);
    if (eq) {
        *value = eq + 1;
    } else {
        if (*i + 1 >= argc) fail(EXIT_USAGE, "%s: %s needs a value", cmd, name);
        *value = argv[++*i];
    }
}

static double real_option(const char *cmd, const char *name, const char *value)
{
    double v;
    if (parse_real(value, &v) != 0)
        fail(EXIT_USAGE, "%s: %s needs a finite number, got '%s'", cmd, name, value);
    return v;
}

/* Handles --rule, --form, --tau-c, --lambda, --ms-max, --deriv-filter;
 * returns 0 when name is none of them. */
static int tune_option(const char *cmd, const char *name, const char *value, tune_opts_t *t)
{
    if (strcmp(name, "--rule") == 0) {
        for (size_t k = 0; k < 4; k++)
            if (strcmp(value, rule_names[k]) == 0) {
                t->rule = (pdt_tune_rule_t)k;
                return 1;
            }
        fail(EXIT_USAGE, "%s: unknown rule '%s' (simc, imc, amigo or zn)", cmd, value);
    }
    if (strcmp(name, "--form") == 0) {
        if (strcmp(value, "pi") == 0)
            t->form = PDT_TUNE_PI;
        else if (strcmp(value, "pid") == 0)
            t->form = PDT_TUNE_PID;
        else
            fail(EXIT_USAGE, "%s: unknown form '%s' (pi or pid)", cmd, value);
        return 1;
    }
    if (strcmp(name, "--tau-c") == 0) {
        t->tau_c = real_option(cmd, name, value);
        if (!(t->tau_c >= 0.0))
            fail(EXIT_USAGE, "%s: --tau-c needs a time >= 0 s (0: the dead time), got '%s'", cmd,
                 value);
        t->have_tau_c = 1;
        return 1;
    }
    if (strcmp(name, "--lambda") == 0) {
        t->lambda = real_option(cmd, name, value);
        if (!(t->lambda >= 0.0))
            fail(EXIT_USAGE, "%s: --lambda needs a time >= 0 s (0: the rule's default), got '%s'",
                 cmd, value);
        t->have_lambda = 1;
        return 1;
    }
    if (strcmp(name, "--ms-max") == 0) {
        t->ms_max = real_option(cmd, name, value);
        if (!(t->ms_max == 0.0 || t->ms_max > 1.0))
            fail(EXIT_USAGE, "%s: --ms-max needs a limit > 1 (or 0 for none), got '%s'", cmd,
                 value);
        t->have_ms_max = 1;
        return 1;
    }
    if (strcmp(name, "--deriv-filter") == 0) {
        t->deriv_filter = real_option(cmd, name, value);
        if (!(t->deriv_filter == 0.0 || t->deriv_filter >= 1.0))
            fail(EXIT_USAGE, "%s: --deriv-filter needs N >= 1 (or 0 for none), got '%s'", cmd,
                 value);
        t->have_filter = 1;
        return 1;
    }
    return 0;
}

static void tune_opts_check(const char *cmd, const tune_opts_t *t)
{
    if (t->have_tau_c && t->rule != PDT_TUNE_SIMC)
        fail(EXIT_USAGE, "%s: --tau-c is the knob of --rule simc only", cmd);
    if (t->have_lambda && t->rule != PDT_TUNE_IMC)
        fail(EXIT_USAGE, "%s: --lambda is the knob of --rule imc only", cmd);
}

static void tune_config(const tune_opts_t *t, pdt_tune_config_t *cfg)
{
    cfg->rule = t->rule;
    cfg->form = t->form;
    if (t->have_tau_c) cfg->tau_c = (pdt_real_t)t->tau_c;
    if (t->have_lambda) cfg->lambda = (pdt_real_t)t->lambda;
    if (t->have_ms_max) cfg->ms_max = (pdt_real_t)t->ms_max;
    if (t->have_filter) cfg->deriv_filter = (pdt_real_t)t->deriv_filter;
}

static void print_gains(const pdt_tune_gains_t *g)
{
    fputs("\"Kc\":", stdout);
    json_num((double)g->Kc);
    json_key("tauI", (double)g->tauI);
    json_key("tauD", (double)g->tauD);
    json_key("Tf", (double)g->Tf);
}

/* The tuning result as one JSON object (no line end). fig NULL: no model,
 * the figures are null. Ku, Pu: echoed when finite (zn from a relay). */
static void print_tune_object(pdt_tune_rule_t rule, pdt_tune_form_t form,
                              const pdt_tune_result_t *r, const pdt_tune_figures_t *fig,
                              double Ku, double Pu)
{
    printf("{\"rule\":\"%s\",\"form\":\"%s\",", rule_names[rule], form_names[form]);
    print_gains(&r->ideal);
    const double nan = (double)NAN;
    json_key("Ms", fig ? (double)fig->Ms : nan);
    json_key("gain_margin", fig ? (double)fig->gain_margin : nan);
    json_key("phase_margin_deg", fig ? (double)fig->phase_margin_deg : nan);
    json_key("w_ms", fig ? (double)fig->w_ms : nan);
    json_key("w_pc", fig && fig->w_pc > 0 ? (double)fig->w_pc : nan);
    json_key("w_gc", fig ? (double)fig->w_gc : nan);
    fputs(",\"series\":", stdout);
    if (r->series_exists || r->series_rule) {
        fputc('{', stdout);
        print_gains(&r->series);
        fputc('}', stdout);
    } else {
        fputs("null", stdout);
    }
    printf(",\"stated_in\":\"%s\"", r->series_rule ? "series" : "ideal");
    if (rule == PDT_TUNE_SIMC) json_key("tau_c", (double)r->knob);
    if (rule == PDT_TUNE_IMC) json_key("lambda", (double)r->knob);
    if (isfinite(Ku)) json_key("Ku", Ku);
    if (isfinite(Pu)) json_key("Pu", Pu);
    fputc('}', stdout);
}

static const char *tune_hint(pdt_status_t st)
{
    switch (st) {
    case PDT_ERR_NO_FORM:
        return " (complex SOPDT poles: only simc and imc pid apply; zn needs a model whose "
               "phase reaches -180 degrees)";
    case PDT_ERR_UNSTABLE:
        return " (the loop these gains make with the model is unstable)";
    case PDT_ERR_ARG:
        return " (the rule needs dead time: simc with tau_c + Td = 0, amigo with Td = 0; or a "
               "value out of the real type's range)";
    default:
        return "";
    }
}

/* Why the gains were refused, for a POOR_FIT from the Ms limit: the Ms
 * they would have had. */
static void fail_ms(const pdt_model_t *m, const pdt_tune_config_t *cfg, const char *cmd)
{
    pdt_tune_config_t open = *cfg;
    open.ms_max = 0;
    pdt_tune_result_t r;
    if (pdt_tune_compute(m, 100, &open, &r) == PDT_OK)
        fail(EXIT_REFUSED, "%s: gains refused: Ms %.4g exceeds the limit %.4g (--ms-max 0 "
             "prints them)", cmd, (double)r.fig.Ms, (double)cfg->ms_max);
    fail(EXIT_REFUSED, "%s: gains refused: %s", cmd, pdt_status_str(PDT_ERR_POOR_FIT));
}

static int cmd_tune(int argc, char **argv)
{
    for (int i = 0; i < argc; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) print_help();
    static const char *const valued[] = {"--rule", "--form", "--tau-c", "--lambda",
                                         "--ms-max", "--deriv-filter", "--model", "--K",
                                         "--tau", "--Td", "--wn", "--zeta", "--tau1",
                                         "--tau2", "--Ku", "--Pu"};
    /* Index in valued - 7 of each model number. */
    enum { P_K, P_TAU, P_TD, P_WN, P_ZETA, P_TAU1, P_TAU2, P_KU, P_PU, P_COUNT };
    double par[P_COUNT];
    int have[P_COUNT] = {0};
    tune_opts_t t;
    memset(&t, 0, sizeof t);
    int have_rule = 0, model = 0; /* 0 none, 1 fopdt, 2 sopdt */
    for (int i = 0; i < argc; i++) {
        char name[32];
        const char *value;
        take_option(argc, argv, &i, "tune", valued, sizeof valued / sizeof valued[0], name,
                    &value);
        if (strcmp(name, "--rule") == 0) have_rule = 1;
        if (tune_option("tune", name, value, &t)) continue;
        if (strcmp(name, "--model") == 0) {
            if (strcmp(value, "fopdt") == 0)
                model = 1;
            else if (strcmp(value, "sopdt") == 0)
                model = 2;
            else
                fail(EXIT_USAGE, "tune: unknown model '%s' (fopdt or sopdt)", value);
            continue;
        }
        for (size_t k = 7; k < sizeof valued / sizeof valued[0]; k++)
            if (strcmp(name, valued[k]) == 0) {
                par[k - 7] = real_option("tune", name, value);
                have[k - 7] = 1;
            }
    }
    if (!have_rule) fail(EXIT_USAGE, "tune: --rule simc|imc|amigo|zn is required");
    tune_opts_check("tune", &t);
    const int relay = have[P_KU] || have[P_PU];
    if (relay) {
        if (t.rule != PDT_TUNE_ZN)
            fail(EXIT_USAGE, "tune: --Ku and --Pu are inputs of --rule zn only");
        if (!have[P_KU] || !have[P_PU]) fail(EXIT_USAGE, "tune: --Ku and --Pu go together");
        if (par[P_KU] == 0.0) fail(EXIT_USAGE, "tune: --Ku must not be 0");
        if (!(par[P_PU] > 0.0)) fail(EXIT_USAGE, "tune: --Pu needs a period > 0 s");
    }
    static const char *const pname[P_COUNT] = {"--K", "--tau", "--Td", "--wn", "--zeta",
                                               "--tau1", "--tau2", "--Ku", "--Pu"};
    if (!model) {
        if (!relay)
            fail(EXIT_USAGE, "tune: --model fopdt|sopdt is required (or --Ku and --Pu with "
                 "--rule zn)");
        for (int k = 0; k < P_KU; k++)
            if (have[k]) fail(EXIT_USAGE, "tune: %s needs --model", pname[k]);
    }
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    if (model) {
        int allowed[P_COUNT] = {0};
        allowed[P_K] = allowed[P_TD] = allowed[P_KU] = allowed[P_PU] = 1;
        if (model == 1) {
            allowed[P_TAU] = 1;
        } else {
            const int natural = have[P_WN] || have[P_ZETA];
            const int tc = have[P_TAU1] || have[P_TAU2];
            if (natural && tc)
                fail(EXIT_USAGE, "tune: give the sopdt as --wn --zeta or as --tau1 --tau2, "
                     "not both");
            allowed[P_WN] = allowed[P_ZETA] = !tc;
            allowed[P_TAU1] = allowed[P_TAU2] = !natural;
        }
        for (int k = 0; k < P_COUNT; k++)
            if (have[k] && !allowed[k])
                fail(EXIT_USAGE, "tune: %s is not a parameter of --model %s", pname[k],
                     model == 1 ? "fopdt" : "sopdt (--K, --Td and --wn, --zeta or --tau1, "
                                            "--tau2)");
        const int need1[] = {P_K, P_TAU, P_TD};
        const int need2n[] = {P_K, P_WN, P_ZETA, P_TD};
        const int need2t[] = {P_K, P_TAU1, P_TAU2, P_TD};
        const int *need = model == 1 ? need1 : (have[P_TAU1] || have[P_TAU2]) ? need2t : need2n;
        const int n_need = model == 1 ? 3 : 4;
        for (int k = 0; k < n_need; k++)
            if (!have[need[k]])
                fail(EXIT_USAGE, "tune: --model %s needs %s", model == 1 ? "fopdt" : "sopdt",
                     pname[need[k]]);
        if (par[P_K] == 0.0) fail(EXIT_USAGE, "tune: --K must not be 0");
        if (!(par[P_TD] >= 0.0)) fail(EXIT_USAGE, "tune: --Td needs a dead time >= 0 s");
        for (int k = P_TAU; k <= P_TAU2; k++)
            if (k != P_TD && have[k] && !(par[k] > 0.0))
                fail(EXIT_USAGE, "tune: %s must be > 0", pname[k]);
        pdt_status_t st = PDT_OK;
        if (model == 1) {
            m.kind = PDT_MODEL_FOPDT;
            m.p.fopdt.K = (pdt_real_t)par[P_K];
            m.p.fopdt.tau = (pdt_real_t)par[P_TAU];
            m.p.fopdt.Td = (pdt_real_t)par[P_TD];
            st = pdt_model_check(&m);
        } else if (have[P_WN]) {
            m.kind = PDT_MODEL_SOPDT;
            const pdt_model_natural_t nat = {(pdt_real_t)par[P_K], (pdt_real_t)par[P_WN],
                                             (pdt_real_t)par[P_ZETA], (pdt_real_t)par[P_TD]};
            st = pdt_model_sopdt_from_natural(&nat, &m.p.sopdt);
        } else {
            m.kind = PDT_MODEL_SOPDT;
            const pdt_model_tc_t tc = {(pdt_real_t)par[P_K], (pdt_real_t)par[P_TAU1],
                                       (pdt_real_t)par[P_TAU2], false, (pdt_real_t)par[P_TD]};
            st = pdt_model_sopdt_from_tc(&tc, &m.p.sopdt);
        }
        if (st == PDT_OK) st = pdt_model_check(&m);
        if (st != PDT_OK)
            fail(EXIT_USAGE, "tune: the model is out of the real type's range (%s)",
                 pdt_status_str(st));
    }

    pdt_tune_config_t cfg;
    pdt_tune_config_default(&cfg);
    tune_config(&t, &cfg);
    pdt_tune_result_t r;
    memset(&r, 0, sizeof r);
    double Ku = (double)NAN, Pu = (double)NAN;
    int have_fig = model != 0;
    if (relay) {
        Ku = par[P_KU];
        Pu = par[P_PU];
        pdt_status_t st = pdt_tune_ziegler_nichols((pdt_real_t)Ku, (pdt_real_t)Pu, t.form,
                                                   &r.ideal);
        if (st != PDT_OK)
            fail(EXIT_REFUSED, "tune: cannot tune: %s (Ku or Pu out of the real type's range)",
                 pdt_status_str(st));
        r.series_exists = pdt_tune_to_series(&r.ideal, &r.series) == PDT_OK;
        if (model) {
            st = pdt_tune_robustness(&m, &r.ideal, &r.fig);
            if (st != PDT_OK)
                fail(EXIT_REFUSED, "tune: cannot tune: %s%s", pdt_status_str(st),
                     tune_hint(st));
            if (cfg.ms_max > 0 && r.fig.Ms > cfg.ms_max)
                fail(EXIT_REFUSED, "tune: gains refused: Ms %.4g exceeds the limit %.4g "
                     "(--ms-max 0 prints them)", (double)r.fig.Ms, (double)cfg.ms_max);
        }
    } else {
        pdt_status_t st = pdt_tune_compute(&m, 100, &cfg, &r);
        if (st == PDT_ERR_POOR_FIT) fail_ms(&m, &cfg, "tune");
        if (st != PDT_OK)
            fail(EXIT_REFUSED, "tune: cannot tune: %s%s", pdt_status_str(st), tune_hint(st));
    }
    print_tune_object(t.rule, t.form, &r, have_fig ? &r.fig : NULL, Ku, Pu);
    fputc('\n', stdout);
    if (fflush(stdout) != 0 || ferror(stdout)) fail(EXIT_REFUSED, "cannot write the result");
    return 0;
}

/* ---------------------------------------------------------- autotune-sim */

/* Deterministic Gaussian noise: xorshift64* and Box-Muller. */
typedef struct noise_gen {
    uint64_t s;
    int have_spare;
    double spare;
} noise_gen_t;

static double noise_uniform(noise_gen_t *g)
{
    g->s ^= g->s >> 12;
    g->s ^= g->s << 25;
    g->s ^= g->s >> 27;
    uint64_t v = g->s * 2685821657736338717ull;
    return ((double)(v >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

static double noise_gauss(noise_gen_t *g)
{
    if (g->have_spare) {
        g->have_spare = 0;
        return g->spare;
    }
    double r = sqrt(-2.0 * log(noise_uniform(g)));
    double a = 6.283185307179586 * noise_uniform(g);
    g->spare = r * sin(a);
    g->have_spare = 1;
    return r * cos(a);
}

/* First frequency (rad/s) where the plant's phase, its gain's sign aside,
 * reaches -180 degrees; 0 if it never does on 1e-4 .. 1e4 / T. */
static double plant_ultimate_w(const double *lags, int n_lags, const double *zeros, int n_zeros,
                               double delay, double T)
{
    double prev_w = 0.0;
    for (int k = 0; k <= 800; k++) {
        double w = 1e-4 / T * pow(10.0, (double)k / 100.0);
        double ph = -delay * w;
        for (int i = 0; i < n_lags; i++) ph -= atan(lags[i] * w);
        for (int j = 0; j < n_zeros; j++) ph += atan(zeros[j] * w);
        if (ph <= -M_PI_VALUE) {
            double lo = prev_w, hi = w;
            for (int it = 0; it < 60; it++) {
                double mid = 0.5 * (lo + hi), pm = -delay * mid;
                for (int i = 0; i < n_lags; i++) pm -= atan(lags[i] * mid);
                for (int j = 0; j < n_zeros; j++) pm += atan(zeros[j] * mid);
                if (pm <= -M_PI_VALUE)
                    hi = mid;
                else
                    lo = mid;
            }
            return 0.5 * (lo + hi);
        }
        prev_w = w;
    }
    return 0.0;
}

static const char *const phase_names[] = {"settle", "excite", "identify", "tune"};
static const char *const kind_names[] = {"", "step", "pulse", "chirp", "prbs", "relay"};

static int cmd_autotune_sim(int argc, char **argv)
{
    for (int i = 0; i < argc; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) print_help();
    static const char *const valued[] = {
        "--rule", "--form", "--tau-c", "--lambda", "--ms-max", "--deriv-filter",
        "--plant-gain", "--plant-lags", "--plant-zeros", "--plant-delay", "--experiment",
        "--amplitude", "--scan-period", "--decimation", "--capacity", "--model", "--noise",
        "--seed", "--u0", "--y0", "--setpoint", "--pv-min", "--pv-max", "--u-min", "--u-max",
        "--trace", "--evaluations"};
    const char *cmd = "autotune-sim";
    tune_opts_t t;
    memset(&t, 0, sizeof t);
    double lags[REDUCE_MAX_LIST], zeros[REDUCE_MAX_LIST];
    int n_lags = -1, n_zeros = 0, have_gain = 0, have_ts = 0, have_sp = 0;
    double gain = 0, delay = 0, amplitude = 1, Ts = 0, noise_std = 0, u0 = 0, y0 = 0, sp = 0;
    int have_lim[4] = {0};
    double lim[4] = {0}; /* pv_min, pv_max, u_min, u_max */
    uint64_t seed = 1, decimation = 0, capacity = 0, evaluations = 0;
    pdt_excite_kind_t kind = PDT_EXCITE_PRBS;
    pdt_model_kind_t model = PDT_MODEL_FOPDT;
    const char *trace = NULL;
    for (int i = 0; i < argc; i++) {
        char name[32];
        const char *value;
        take_option(argc, argv, &i, cmd, valued, sizeof valued / sizeof valued[0], name, &value);
        if (tune_option(cmd, name, value, &t)) continue;
        if (strcmp(name, "--plant-gain") == 0) {
            gain = real_option(cmd, name, value);
            if (gain == 0.0) fail(EXIT_USAGE, "%s: --plant-gain must not be 0", cmd);
            have_gain = 1;
        } else if (strcmp(name, "--plant-lags") == 0) {
            n_lags = parse_list(value, lags, REDUCE_MAX_LIST);
            if (n_lags < 0)
                fail(EXIT_USAGE, "%s: --plant-lags needs 1 to %d numbers separated by commas, "
                     "got '%s'", cmd, REDUCE_MAX_LIST, value);
            for (int k = 0; k < n_lags; k++)
                if (!(lags[k] > 0.0))
                    fail(EXIT_USAGE, "%s: --plant-lags: every time constant must be > 0, got "
                         "%.9g", cmd, lags[k]);
        } else if (strcmp(name, "--plant-zeros") == 0) {
            n_zeros = parse_list(value, zeros, REDUCE_MAX_LIST);
            if (n_zeros < 0)
                fail(EXIT_USAGE, "%s: --plant-zeros needs 1 to %d numbers separated by commas, "
                     "got '%s'", cmd, REDUCE_MAX_LIST, value);
            for (int k = 0; k < n_zeros; k++)
                if (zeros[k] == 0.0)
                    fail(EXIT_USAGE, "%s: --plant-zeros: a zero time constant cannot be 0", cmd);
        } else if (strcmp(name, "--plant-delay") == 0) {
            delay = real_option(cmd, name, value);
            if (!(delay >= 0.0))
                fail(EXIT_USAGE, "%s: --plant-delay needs a dead time >= 0 s, got '%s'", cmd,
                     value);
        } else if (strcmp(name, "--experiment") == 0) {
            int found = 0;
            for (int k = 1; k <= 5; k++)
                if (strcmp(value, kind_names[k]) == 0) {
                    kind = (pdt_excite_kind_t)k;
                    found = 1;
                }
            if (!found)
                fail(EXIT_USAGE, "%s: unknown experiment '%s' (step, pulse, chirp, prbs or "
                     "relay)", cmd, value);
        } else if (strcmp(name, "--amplitude") == 0) {
            amplitude = real_option(cmd, name, value);
            if (amplitude == 0.0) fail(EXIT_USAGE, "%s: --amplitude must not be 0", cmd);
        } else if (strcmp(name, "--scan-period") == 0) {
            Ts = real_option(cmd, name, value);
            if (!(Ts > 0.0)) fail(EXIT_USAGE, "%s: --scan-period needs a period > 0 s", cmd);
            have_ts = 1;
        } else if (strcmp(name, "--decimation") == 0) {
            if (parse_u64(value, &decimation) != 0 || decimation == 0 || decimation > 1000000)
                fail(EXIT_USAGE, "%s: --decimation needs a whole number 1 .. 1000000, got '%s'",
                     cmd, value);
        } else if (strcmp(name, "--capacity") == 0) {
            if (parse_u64(value, &capacity) != 0 || capacity == 0 || capacity > 100000000)
                fail(EXIT_USAGE, "%s: --capacity needs a whole number 1 .. 100000000, got '%s'",
                     cmd, value);
        } else if (strcmp(name, "--evaluations") == 0) {
            if (parse_u64(value, &evaluations) != 0 || evaluations == 0 ||
                evaluations > UINT32_MAX)
                fail(EXIT_USAGE, "%s: --evaluations needs a whole number >= 1, got '%s'", cmd,
                     value);
        } else if (strcmp(name, "--model") == 0) {
            if (strcmp(value, "fopdt") == 0)
                model = PDT_MODEL_FOPDT;
            else if (strcmp(value, "sopdt") == 0)
                model = PDT_MODEL_SOPDT;
            else
                fail(EXIT_USAGE, "%s: unknown model '%s' (fopdt or sopdt)", cmd, value);
        } else if (strcmp(name, "--noise") == 0) {
            noise_std = real_option(cmd, name, value);
            if (!(noise_std >= 0.0))
                fail(EXIT_USAGE, "%s: --noise needs a standard deviation >= 0, got '%s'", cmd,
                     value);
        } else if (strcmp(name, "--seed") == 0) {
            if (parse_u64(value, &seed) != 0)
                fail(EXIT_USAGE, "%s: --seed needs a whole number >= 0, got '%s'", cmd, value);
        } else if (strcmp(name, "--u0") == 0) {
            u0 = real_option(cmd, name, value);
        } else if (strcmp(name, "--y0") == 0) {
            y0 = real_option(cmd, name, value);
        } else if (strcmp(name, "--setpoint") == 0) {
            sp = real_option(cmd, name, value);
            have_sp = 1;
        } else if (strcmp(name, "--trace") == 0) {
            trace = value;
        } else {
            static const char *const limits[] = {"--pv-min", "--pv-max", "--u-min", "--u-max"};
            for (int k = 0; k < 4; k++)
                if (strcmp(name, limits[k]) == 0) {
                    lim[k] = real_option(cmd, name, value);
                    have_lim[k] = 1;
                }
        }
    }
    if (!have_gain) fail(EXIT_USAGE, "%s: --plant-gain K is required", cmd);
    if (n_lags < 0) fail(EXIT_USAGE, "%s: --plant-lags T1,T2,... is required", cmd);
    if (n_zeros > n_lags)
        fail(EXIT_USAGE, "%s: more zeros (%d) than lags (%d): the plant is improper", cmd,
             n_zeros, n_lags);
    if (have_sp && kind != PDT_EXCITE_RELAY)
        fail(EXIT_USAGE, "%s: --setpoint is an option of --experiment relay only", cmd);
    if ((have_lim[0] && have_lim[1] && lim[0] > lim[1]) ||
        (have_lim[2] && have_lim[3] && lim[2] > lim[3]))
        fail(EXIT_USAGE, "%s: a lower limit lies above its upper limit", cmd);
    tune_opts_check(cmd, &t);

    /* Defaults from the plant: time scale, dominant lag, settling time. */
    double sum_lags = 0.0, T1 = 0.0;
    for (int k = 0; k < n_lags; k++) {
        sum_lags += lags[k];
        if (lags[k] > T1) T1 = lags[k];
    }
    const double T_scale = sum_lags + delay;
    const double T_settle = 4.0 * sum_lags + delay;
    if (!have_ts) Ts = T_scale / 200.0;
    /* The recorder keeps the output of each interval's first scan: right
     * for an output that changes on interval boundaries (step, pulse,
     * PRBS chips below), late for one that changes at any scan (relay,
     * chirp), which therefore record every scan by default. */
    /* The recorder averages u and pv over each sample, so an output that
     * changes at any scan (chirp, relay) is recorded as well as a step. */
    if (!decimation) decimation = 4u;
    const double Ts_id = Ts * (double)decimation;
    const double wu = plant_ultimate_w(lags, n_lags, zeros, n_zeros, delay, T_scale);
    const uint32_t settle = 20;

    pdt_autotune_config_t cfg;
    pdt_autotune_config_default(&cfg);
    pdt_excite_config_default(&cfg.excite, kind);
    pdt_excite_config_t *ec = &cfg.excite;
    double window = 0.0; /* experiment time after the settle window, s */
    switch (kind) {
    case PDT_EXCITE_STEP:
        ec->amplitude = (pdt_real_t)amplitude;
        ec->duration = 0;
        window = 2.0 * T_settle;
        break;
    case PDT_EXCITE_PULSE:
        ec->amplitude = (pdt_real_t)amplitude;
        /* Whole identification samples, as the PRBS chips. */
        double on = floor(0.5 * T_settle / Ts_id + 0.5);
        ec->t_on = (pdt_real_t)((on < 1.0 ? 1.0 : on) * Ts_id);
        ec->t_off = (pdt_real_t)(floor(T_settle / Ts_id + 0.5) * Ts_id);
        ec->count = 1;
        window = 2.0 * T_settle;
        break;
    case PDT_EXCITE_CHIRP: {
        ec->amplitude = (pdt_real_t)fabs(amplitude);
        double f1 = (wu > 0.0 ? 1.5 * wu : 3.0 / T1) / (2.0 * M_PI_VALUE);
        if (f1 > 0.25 / Ts) f1 = 0.25 / Ts;
        ec->f0 = 0;
        ec->f1 = (pdt_real_t)f1;
        ec->duration = (pdt_real_t)(5.0 * T_settle);
        window = 6.0 * T_settle;
        break;
    }
    case PDT_EXCITE_PRBS: {
        ec->amplitude = (pdt_real_t)fabs(amplitude);
        ec->prbs_bits = 6;
        /* Chips of whole identification samples: the recorder keeps the
         * output of an interval's first scan, so a change inside an
         * interval would be recorded late. */
        double chips = floor(T1 / Ts_id + 0.5);
        double hold = (chips < 1.0 ? 1.0 : chips) * (double)decimation;
        ec->prbs_hold = hold > 1e8 ? 100000000u : (uint32_t)hold;
        ec->periods = 1;
        window = 63.0 * (double)ec->prbs_hold * Ts + T_settle;
        break;
    }
    case PDT_EXCITE_RELAY:
    default: {
        ec->d = (pdt_real_t)fabs(amplitude);
        ec->setpoint = (pdt_real_t)(have_sp ? sp : y0);
        ec->eps = (pdt_real_t)(3.0 * noise_std);
        ec->action = gain > 0.0 ? PDT_EXCITE_REVERSE : PDT_EXCITE_DIRECT;
        const double Pu = wu > 0.0 ? 2.0 * M_PI_VALUE / wu : 2.0 * T_scale;
        window = 8.0 * Pu + T_settle;
        break;
    }
    }
    if (!capacity) {
        double c = (double)settle + ceil(window / Ts_id);
        capacity = c > 1e8 ? 100000000u : (uint64_t)c;
    }
    cfg.Ts = (pdt_real_t)Ts;
    cfg.decimation = (uint32_t)decimation;
    cfg.capacity = (size_t)capacity;
    cfg.settle = settle;
    if (have_lim[0]) cfg.pv_min = (pdt_real_t)lim[0];
    if (have_lim[1]) cfg.pv_max = (pdt_real_t)lim[1];
    if (have_lim[2]) cfg.u_min = (pdt_real_t)lim[2];
    if (have_lim[3]) cfg.u_max = (pdt_real_t)lim[3];
    cfg.ident.model = model;
    cfg.ident.seed = seed;
    if (evaluations) cfg.ident.max_evaluations = (uint32_t)evaluations;
    tune_config(&t, &cfg.tune);

    plant_sim_t plant;
    if (plant_init(&plant, gain, lags, (size_t)n_lags, zeros, (size_t)n_zeros, delay, Ts,
                   u0, y0) != 0)
        fail(EXIT_REFUSED, "out of memory");
    FILE *tf = NULL;
    if (trace) {
        tf = fopen(trace, "w");
        if (!tf) fail(EXIT_USAGE, "cannot open %s: %s", trace, strerror(errno));
        fputs("t,u,pv\n", tf);
    }

    pdt_autotune_t *at = malloc(sizeof *at);
    if (!at) fail(EXIT_REFUSED, "out of memory");
    size_t work_len = pdt_autotune_workspace_size(&cfg);
    void *work = work_len ? malloc(work_len) : NULL;
    if (work_len && !work) fail(EXIT_REFUSED, "out of memory (%zu bytes of workspace)", work_len);
    noise_gen_t ng = {seed * 0x9E3779B97F4A7C15ull + 0x2545F4914F6CDD1Dull, 0, 0.0};
    if (ng.s == 0) ng.s = 1;

    uint32_t phase_scans[4] = {0};
    uint64_t scans = 0;
    pdt_autotune_result_t res;
    memset(&res, 0, sizeof res);
    pdt_status_t st = pdt_autotune_init(at, &cfg, (pdt_real_t)u0, work, work_len);
    int initialised = st == PDT_OK;
    /* Scans can only end the experiment (capacity, relay) and the search
     * (its evaluations); this bound only guards the host against a bug. */
    const uint64_t guard = 4ull * capacity * decimation + 10000000ull;
    while (st == PDT_OK && initialised) {
        double pv = plant_output(&plant);
        if (noise_std > 0.0) pv += noise_std * noise_gauss(&ng);
        pdt_autotune_phase_t ph = pdt_autotune_phase(at);
        if (ph >= PDT_AUTOTUNE_SETTLE && ph <= PDT_AUTOTUNE_TUNE) phase_scans[ph - 1]++;
        pdt_real_t u;
        pdt_status_t ss = pdt_autotune_scan(at, (pdt_real_t)pv, &u);
        if (tf) fprintf(tf, "%.9g,%.9g,%.9g\n", (double)scans * Ts, (double)u, pv);
        plant_advance(&plant, (double)u);
        scans++;
        if (ss == PDT_RUNNING && scans < guard) continue;
        if (ss == PDT_RUNNING) (void)pdt_autotune_abort(at, &u);
        break;
    }
    if (initialised) {
        (void)pdt_autotune_result(at, &res);
        st = res.status;
    }
    if (tf && (fflush(tf) != 0 || ferror(tf) || fclose(tf) != 0))
        fail(EXIT_REFUSED, "cannot write %s", trace);

    printf("{\"status\":\"%s\",\"reason\":\"%s\"", status_name(st), pdt_status_str(st));
    if (st != PDT_OK) {
        static const char *const failed[] = {"init",     "settle", "excite", "identify",
                                             "tune",     "done",   "failed"};
        int fi = initialised ? (int)res.failed_in : 0;
        printf(",\"failed_in\":\"%s\"", fi >= 0 && fi <= 6 ? failed[fi] : "unknown");
    }
    json_key("scan_period", Ts);
    printf(",\"decimation\":%lu,\"capacity\":%lu,\"samples\":%lu,\"scans\":%lu",
           (unsigned long)decimation, (unsigned long)capacity, (unsigned long)res.samples,
           (unsigned long)scans);
    printf(",\"experiment\":{\"kind\":\"%s\"", kind_names[kind]);
    json_key("duration", (double)res.scans_experiment * Ts);
    printf(",\"scans\":%lu", (unsigned long)res.scans_experiment);
    switch (kind) {
    case PDT_EXCITE_STEP:
        json_key("amplitude", (double)ec->amplitude);
        break;
    case PDT_EXCITE_PULSE:
        json_key("amplitude", (double)ec->amplitude);
        json_key("t_on", (double)ec->t_on);
        json_key("t_off", (double)ec->t_off);
        break;
    case PDT_EXCITE_CHIRP:
        json_key("amplitude", (double)ec->amplitude);
        json_key("f0", (double)ec->f0);
        json_key("f1", (double)ec->f1);
        json_key("sweep", (double)ec->duration);
        break;
    case PDT_EXCITE_PRBS:
        json_key("amplitude", (double)ec->amplitude);
        printf(",\"bits\":%u", (unsigned)ec->prbs_bits);
        json_key("hold", (double)ec->prbs_hold * Ts);
        break;
    default:
        json_key("d", (double)ec->d);
        json_key("eps", (double)ec->eps);
        json_key("setpoint", (double)ec->setpoint);
        printf(",\"action\":\"%s\"", ec->action == PDT_EXCITE_REVERSE ? "reverse" : "direct");
        break;
    }
    fputs("},\"phases\":{", stdout);
    for (int k = 0; k < 4; k++)
        printf("%s\"%s\":%lu", k ? "," : "", phase_names[k], (unsigned long)phase_scans[k]);
    fputs("},\"ident\":", stdout);
    if (res.has_model)
        print_model_object(&res.ident.model, &res.ident);
    else
        fputs("null", stdout);
    fputs(",\"tune\":", stdout);
    if (res.has_gains)
        print_tune_object(t.rule, t.form, &res.tune, &res.tune.fig, (double)NAN, (double)NAN);
    else
        fputs("null", stdout);
    if (kind == PDT_EXCITE_RELAY) {
        fputs(",\"relay\":", stdout);
        if (res.has_relay) {
            fputs("{\"Ku\":", stdout);
            json_num((double)res.relay.Ku);
            json_key("Pu", (double)res.relay.Pu);
            json_key("a", (double)res.relay.a);
            json_key("d", (double)res.relay.d);
            printf(",\"cycles\":%u}", (unsigned)res.relay.cycles);
        } else {
            fputs("null", stdout);
        }
    }
    fputs("}\n", stdout);
    if (fflush(stdout) != 0 || ferror(stdout)) fail(EXIT_REFUSED, "cannot write the result");
    free(work);
    free(at);
    plant_free(&plant);
    if (st != PDT_OK) {
        static const char *const phase_of[] = {"init", "settle", "excite", "identify", "tune"};
        const int fi = initialised ? (int)res.failed_in : 0;
        const char *where = fi >= 0 && fi <= 4 ? phase_of[fi] : "?";
        if (st == PDT_ERR_POOR_FIT && res.has_model && res.ident.fit < cfg.tune.fit_min)
            fail(EXIT_REFUSED, "autotune-sim: %s (%s in %s): fit %.4g%% below %.4g%%: too much "
                 "noise or too little excitation", pdt_status_str(st), status_name(st), where,
                 (double)res.ident.fit, (double)cfg.tune.fit_min);
        if (st == PDT_ERR_POOR_FIT && res.has_model) {
            pdt_tune_config_t open = cfg.tune;
            open.ms_max = 0;
            pdt_tune_result_t tr;
            if (pdt_tune_compute(&res.ident.model, res.ident.fit, &open, &tr) == PDT_OK)
                fail(EXIT_REFUSED, "autotune-sim: %s (%s in %s): Ms %.4g exceeds the limit %.4g "
                     "(--ms-max, a slower knob or another rule)", pdt_status_str(st),
                     status_name(st), where, (double)tr.fig.Ms, (double)cfg.tune.ms_max);
        }
        fail(EXIT_REFUSED, "autotune-sim: %s (%s in %s)", pdt_status_str(st), status_name(st),
             where);
    }
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
    if (strcmp(cmd, "tune") == 0) return cmd_tune(argc - 2, argv + 2);
    if (strcmp(cmd, "autotune-sim") == 0) return cmd_autotune_sim(argc - 2, argv + 2);
    fail(EXIT_USAGE, "unknown command '%s' (see pdtfit --help)", cmd);
    return EXIT_USAGE;
}
