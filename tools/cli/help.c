/* The help of the command line: one section per subcommand. */
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"

const char cli_usage[] =
    "usage: pdtfit identify --model fopdt|sopdt|auto [--method ga|elms|eiv] [options] FILE.csv\n"
    "       pdtfit reduce --method skogestad|sung --model fopdt|sopdt --gain K\n"
    "                     --lags T1,T2,... [--zeros Z1,...] [--delay D] [--h H]\n"
    "       pdtfit tune --rule simc|imc|amigo|zn [--form pi|pid] --model fopdt|sopdt\n"
    "                   --K K --Td D (--tau T | --wn W --zeta Z | --tau1 T1 --tau2 T2)\n"
    "       pdtfit tune --rule RULE [--form pi|pid] --from FILE.json|-\n"
    "       pdtfit tune --rule zn [--form pi|pid] --Ku KU --Pu PU\n"
    "       pdtfit autotune-sim --plant-gain K --plant-lags T1,... [options]\n"
    "       pdtfit monitor [--model FILE.json] FILE.csv\n"
    "       pdtfit COMMAND --help | pdtfit --help | pdtfit --version\n";

/* In paragraphs: ISO C99 compilers need only take 4095-character strings. */
static const char *const identify_text[] = {
    "\n"
    "identify: a first- or second-order-plus-dead-time model of a process from\n"
    "one recorded test (Yang and Seested 2013: a genetic-algorithm search\n"
    "followed by a local refinement), printed as one JSON object.\n"
    "  --model fopdt|sopdt|auto  the model (required):\n"
    "                          fopdt  K e^(-Td s) / (tau s + 1)\n"
    "                          sopdt  K wn^2 e^(-Td s) / (s^2 + 2 zeta wn s + wn^2)\n"
    "                          auto   both, and the one the evidence supports\n"
    "                                 (residual tests, uncertainty, BIC; ga only)\n"
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
    "                        ga a third of the record, elms/eiv a quarter\n",
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
    "  --uncertainty KIND    how std, cov and ci95 are found (ga only): auto (the\n"
    "                        bootstrap for a sopdt, fisher for a fopdt), fisher,\n"
    "                        bootstrap\n"
    "  --bootstrap N         the bootstrap's runs (default 50)\n"
    "  --offset KIND         the output operating point y0 (ga only):\n"
    "                          auto      (default) rest when the record starts\n"
    "                                    with the input still and the output\n"
    "                                    flat for at least n/40 samples, else\n"
    "                                    estimate\n"
    "                          estimate  fitted with the model\n"
    "                          rest      the output's mean before the input\n"
    "                                    first moves\n"
    "  --initial auto|rest|estimate  the state at the record's start (ga only):\n"
    "                        auto (default) at rest, tested: a record cut\n"
    "                        mid-transient is identified again with the state\n"
    "                        estimated, and keeps the flag mid_transient where\n"
    "                        that does not explain its start; rest: not tested;\n"
    "                        estimate: the model's free response from the first\n"
    "                        row fitted with the gain and offset (--cost\n"
    "                        simulation)\n"
    "  --drift               fit a linear drift of the output too (units of y per\n"
    "                        second, about the record's middle; --cost simulation)\n"
    "  --u-before U          the input before the first row, for a record that\n"
    "                        begins at the step (ga only; not with --model auto);\n"
    "                        default: the first row's u\n"
    "  --phi-t X, --phi-f X  weights of the time and frequency parts of combined,\n"
    "                        >= 0 (default 1 and 1)\n"
    "  --seed N              seed of the search's random numbers (default 1); the\n"
    "                        same seed, data and build give the same output\n",
    /* NULL: the lines that show the library's own defaults go here. */
    NULL,
    "  --integer-delay       dead time in whole samples, as in the paper (default:\n"
    "                        fractional dead time with an exact sampled model)\n"
    "  --tune RULE[:FORM]    also tune (as pdtfit tune): adds \"tune\" to the JSON;\n"
    "                        --tau-c, --lambda, --ms-max, --deriv-filter, --u-span,\n"
    "                        --y-span, --fit-min as for tune; a flagged model is\n"
    "                        refused (exit 3) unless --force\n"
    "  --out-sim FILE.csv    write t,u,y,ysim,residual (t from 0, every Ts)\n"
    "  --plot FILE.png       draw data, model and residual (python3 + matplotlib;\n"
    "                        the script: --plot-script PATH, $PDTFIT_PLOT_SCRIPT,\n"
    "                        or tools/plot_fit.py beside the program)\n",
    "\n"
    "FILE.csv ('-' reads standard input): a header row naming the columns, then\n"
    "  one row per sample; lines starting with '#' are skipped.\n"
    "  --t COL, --u COL, --y COL  the time, input and output columns, by name\n"
    "                        (any case; with or without its unit: \"CV [%]\" or CV)\n"
    "                        or by 1-based index. Default t (time, timestamp), u, y (pv)\n"
    "  --sep C               separator ',', ';' or tab (default: found in the header)\n"
    "  --decimal C           '.' or ','; a ',' is read as a decimal point anyway when\n"
    "                        the separator is ';' or tab\n"
    "  --skip N              lines before the header (a logger's preamble)\n"
    "  --units-row           one row of units under the header, skipped (found\n"
    "                        and reported without it)\n"
    "  --time-unit s|ms|us|min|h  unit of numeric t (default: the header's,\n"
    "                        \"t [ms]\", \"time_ms\", else s; epoch ms or us read as\n"
    "                        s are refused; date-times are read as such)\n"
    "  --time-format FMT     t's date-time form: %Y %y %m %d %H %I %M %S %f %p %z;\n"
    "                        found without it: ISO 8601, 01.03.2024 08:00:00,500,\n"
    "                        3/1/2024 8:00:00 AM\n"
    "  --bad-value V[,V...]  declared bad values (-9999): missing samples; repeatable\n"
    "  --bad-rows missing|refuse  missing samples (empty cells, NaN, #N/A, ERR,\n"
    "                        #VALUE!, bad values): left out of the fit (y) or the\n"
    "                        u before held (u), counted (default); or refused\n"
    "  --fs HZ               sampling frequency; required without a t column,\n"
    "                        else it must agree with t within 1% and is used\n"
    "  --resample            fill gaps in t (dropped rows) by zero-order hold on the\n"
    "                        grid of Ts, and say how many rows were added\n"
    "  t: increasing; each interval within 25% of the median (more than 1% off:\n"
    "  a warning, and Ts is the median); a gap, a duplicate or a step back is\n"
    "  refused with its line. u: process input, y: process output, engineering\n"
    "  units, numbers or missing samples; at least 16 rows; the record starts at\n"
    "  rest.\n",
    "\n"
    "Output: one JSON object on one line, numbers with 9 significant digits,\n"
    "null where a value does not exist.\n"
    "  fopdt: "
    "{\"model\":\"fopdt\",\"K\",\"tau\",\"Td\",\"y0\",\"u0\",\"cost\",\"fit\",\"evaluations\",\n"
    "          \"Ts\",\"n\"}\n"
    "  sopdt: {\"model\":\"sopdt\",\"K\",\"wn\",\"zeta\",\"Td\",\"y0\",\"u0\",\"tau1\",\"tau2\",\n"
    "          \"a\",\"b\",\"cost\",\"fit\",\"evaluations\",\"Ts\",\"n\"}\n"
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
    "    Ts, n  the sampling period used, s, and the samples identified\n"
    "  ga adds \"searches\", \"coarse\", \"runner_up\", \"flags\" (what the search\n"
    "  could not settle; \"no_relation\": the model is no better than y's mean),\n"
    "  \"evidence\" (its likelihood ratio against y's mean) and \"excluded\"\n"
    "  ({\"count\",\"missing\",\"first\"}: samples of y left out of the fit as\n"
    "  missing or gross errors, also named on stderr). A flag exits 3.\n"
    "  Integrating process (sopdt with b = 0, Ki e^(-Td s) / (s (tau2 s + 1))):\n"
    "    \"K\":null, \"Ki\" (after \"K\"): integrating gain, output units per input\n"
    "    unit per second, \"wn\":0, \"zeta\":null, \"tau1\":null, \"tau2\" = 1/a.\n",
};

static const char *const reduce_text[] = {
    "\n"
    "reduce: a FOPDT or SOPDT from a known detailed model\n"
    "  K prod_j (Zj s + 1) / prod_i (Ti s + 1) e^(-D s), printed as identify\n"
    "  prints that model kind, without y0, u0, cost, fit, evaluations, Ts, n.\n"
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
    "      --lags 2,1,0.4,0.2,0.05,0.05,0.05 --zeros -0.3,0.08\n",
};

static const char *const tune_text[] = {
    "\n"
    "tune: PI/PID gains of a known model by a published rule, with the\n"
    "  robustness of the loop they make (pdt_tune.h, docs/tuning.md)\n"
    "  --rule simc|imc|amigo|zn  the rule (required)\n"
    "  --form pi|pid         the controller (default pi)\n"
    "  --model fopdt|sopdt   with --K and --Td, and --tau (fopdt), or --wn and\n"
    "                        --zeta, or --tau1 and --tau2 (sopdt)\n"
    "  --from FILE.json      the model identify printed ('-': standard input):\n"
    "                        pdtfit identify ... | pdtfit tune --rule simc --from -\n"
    "                        its fit is checked as the autotune does; a model\n"
    "                        with a flag or a negative fit is refused (exit 3)\n"
    "  --force               with --from: tune a flagged model anyway (exit 3)\n"
    "  --Ku KU --Pu PU       zn only: ultimate gain and period (e.g. from a relay)\n"
    "                        instead of a model; with a model too, the figures\n"
    "                        are those of these gains on that model\n"
    "  --tau-c X             simc: closed-loop time constant, s (default Td)\n"
    "  --lambda X            imc: closed-loop time constant, s (default\n"
    "                        max(tau, 3 Td))\n"
    "  --ms-max X            refuse gains whose Ms exceeds X (default 2; 0: none)\n"
    "  --deriv-filter N      derivative filter Tf = tauD / N (default 10; 0: none)\n"
    "  --fit-min PCT         refuse gains when the model's fit is below PCT percent\n"
    "                        (default 0: the fit alone decides nothing)\n"
    "  --u-span U --y-span Y the ranges of u and y: adds the gains in percent of\n"
    "                        span (\"percent\")\n"
    "  Prints {\"rule\",\"form\",\"Kc\",\"tauI\",\"tauD\",\"Tf\" (ideal form),\"Ms\",\n"
    "  \"gain_margin\",\"phase_margin_deg\",\"w_ms\",\"w_pc\",\"w_gc\" (rad/s),\n"
    "  \"series\" ({\"Kc\",\"tauI\",\"tauD\",\"Tf\"} or null),\"parallel\" ({\"Kp\",\"Ki\",\n"
    "  \"Kd\",\"Tf\"}: Kp + Ki/s + Kd s/(Tf s + 1)),[\"percent\" (as parallel)],\n"
    "  \"stated_in\", and \"tau_c\" (simc) or \"lambda\" (imc)}. null: infinite or\n"
    "  absent. A pid that comes out without derivative action is said on stderr.\n",
};

static const char *const autotune_text[] = {
    "\n"
    "autotune-sim: the on-device autotune (pdt_autotune) run scan by scan on a\n"
    "  simulated plant K prod (Zj s + 1) / prod (Ti s + 1) e^(-D s)\n"
    "  --plant-gain K, --plant-lags T1,..., --plant-zeros Z1,..., --plant-delay D\n"
    "                        the plant, as for reduce (gain and a pole required)\n"
    "  --plant-wn W --plant-zeta Z  a pole pair 1 / (s^2/W^2 + 2 Z s/W + 1)\n"
    "  --plant-integrating   an integrator 1 / s (K per second)\n"
    "  --experiment KIND     step|pulse|chirp|prbs|relay (default prbs)\n"
    "  --amplitude A         step/pulse change, chirp/prbs half swing, relay d\n"
    "                        (default 1)\n"
    "  --scan-period S       default (sum of lags + D) / 200\n"
    "  --decimation N        scans per identification sample (default 4)\n"
    "  --capacity N          samples recorded (default: settle + the experiment\n"
    "                        + a settling time 4 sum(lags) + D)\n"
    "  --model fopdt|sopdt|auto  identified model (default auto: both, the one\n"
    "                        the evidence supports; fopdt, sopdt fix the order);\n"
    "                        --evaluations N\n"
    "  --rule, --form, --tau-c, --lambda, --ms-max, --deriv-filter, --u-span,\n"
    "  --y-span, --fit-min   as for tune\n"
    "  --noise STD, --seed N Gaussian noise on pv; seed of noise and search\n"
    "  --u0 U, --y0 Y        operating point (default 0, 0)\n"
    "  --setpoint SP         relay set-point (default y0)\n"
    "  After gains, \"loop\" reports them run by pdt_pid on the true plant: Ms,\n"
    "  set-point and load IAE, overshoot.\n"
    "  --pv-min, --pv-max, --u-min, --u-max  safety limits (default none)\n"
    "  --trace FILE          also write t,u,pv of every scan as CSV (identify\n"
    "                        reads it: pv is taken as y); with a fault also\n"
    "                        u_valve (the actuator's position), load and y (the\n"
    "                        plant's output before the sensor)\n"
    "  Faults (docs/autotune.md), any combination, each off by default:\n"
    "  --load-step T:D       a load of D input units at the plant's input from T s\n"
    "  --drift R             pv drifts R units per second\n"
    "  --quantise Q          pv is read in steps of Q\n"
    "  --u-rate R            the actuator moves at most R input units per second\n"
    "  --stiction S          the valve follows the output only once it has moved\n"
    "                        more than S away (backlash of width S)\n"
    "  --shift-max F, --relay-spread-max F, --repeats N, --drift-passes N  the\n"
    "                        disturbance check (defaults 0.08, 0.5, 1, 3; 0 turns\n"
    "                        a check off)\n"
    "  --actuator-position   the autotune reads the valve's position (u_valve) and\n"
    "                        identifies from it (pdt_autotune_scan_position)\n"
    "  --closed-loop --initial-gains Kc,Ti[,Td]  retune with the loop closed: a\n"
    "                        PID with these gains stays in control and the\n"
    "                        experiment moves its set-point by |K| A (step, pulse,\n"
    "                        chirp or prbs); prints \"closed_loop\"\n"
    "  Prints {\"status\" (pdt_status_t, 0 ok),\"reason\",[\"failed_in\"],\n"
    "  \"scan_period\",\"decimation\",\"capacity\",\"samples\",\"scans\",\"experiment\",\n"
    "  \"phases\",\"ident\" (as identify),\"order\" (auto: the order kept, both\n"
    "  BICs),\"tune\" (as tune),\"loop\",[\"relay\"]}; printed also when the\n"
    "  autotune aborts or refuses, with exit status 1 and the reason on stderr.\n",
};

static const char exit_text[] =
    "\n"
    "Exit status: 0 result printed; 1 the data cannot be identified, the model\n"
    "not reduced, gains refused or the autotune aborted (the library's reason is\n"
    "printed, e.g. the input never moves); 2 bad usage or an unreadable or\n"
    "malformed file; 3 identify printed a model that is probably wrong (a\n"
    "negative fit, or a parameter on a bound of the search; the warning is on\n"
    "stderr). Errors are one line on stderr starting \"pdtfit: \"; nothing is\n"
    "printed on stdout then (except autotune-sim's JSON).\n";

static void print_budget(void)
{
    pdt_ident_config_t def;
    pdt_ident_config_default(&def);
    printf("  --evaluations N       cost evaluations in all, search and refinement\n"
           "                        (default %lu; too few are refused with the minimum)\n"
           "  --population N        GA individuals, even, 4 .. %u (default %u for fopdt,\n"
           "                        %u for sopdt)\n"
           "  --coarse D            search a record D times coarser, then polish the\n"
           "                        answer on the whole one (cost simulation with\n"
           "                        fractional dead times; 1: the whole record only;\n"
           "                        default 0: automatic, about %u samples)\n",
           (unsigned long)def.max_evaluations, (unsigned)PDT_IDENT_MAX_POPULATION,
           (unsigned)PDT_IDENT_POPULATION_FOPDT, (unsigned)PDT_IDENT_POPULATION_SOPDT,
           (unsigned)PDT_IDENT_COARSE_SAMPLES);
}

static void print_section(const char *const *text, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (text[i])
            fputs(text[i], stdout);
        else
            print_budget();
    }
}

static const char *const monitor_text[] = {
    "\n"
    "monitor: the loop-performance monitor (pdt_monitor) over one closed-loop\n"
    "record; prints one JSON object whose \"verdict\" is ok, oscillating,\n"
    "sluggish, model_changed, saturated or not_enough_data, with the figures.\n"
    "  --model FILE.json     the process model, as tune --from reads it (identify's\n"
    "                        JSON or the model's own fields). Without it the\n"
    "                        model-based figures (harris, iae_ratio, gain_ratio)\n"
    "                        are null and sluggishness is judged by the idle index\n"
    "  --t, --sp, --pv, --u NAME|INDEX  the columns (default t, sp, pv or y, u)\n"
    "  --sep, --decimal, --skip  as for identify\n"
    "  --u-min, --u-max U    the output's limits; default: an extreme value the\n"
    "                        output holds in at least 2 % of the rows\n"
    "  --horizon N           memory of the statistics, samples; 0 (default): the\n"
    "                        whole record\n"
    "  --decimation N        rows averaged into one sample; default: the least\n"
    "                        that puts the dead time within the monitor's order\n"
    "  --min-samples N       samples before any verdict, >= 16 (default 400)\n",
};

#define SECTION(t) print_section(t, sizeof t / sizeof t[0])

void cli_help(cli_cmd_t which)
{
    fputs(cli_usage, stdout);
    if (which == CMD_ALL || which == CMD_IDENTIFY) SECTION(identify_text);
    if (which == CMD_ALL || which == CMD_REDUCE) SECTION(reduce_text);
    if (which == CMD_ALL || which == CMD_TUNE) SECTION(tune_text);
    if (which == CMD_ALL || which == CMD_AUTOTUNE) SECTION(autotune_text);
    if (which == CMD_ALL || which == CMD_MONITOR) SECTION(monitor_text);
    fputs("\nOptions take their value as the next argument or after '=', once each;\n"
          "choices are case-insensitive.\n",
          stdout);
    fputs(exit_text, stdout);
    exit(fflush(stdout) == 0 && !ferror(stdout) ? 0 : EXIT_REFUSED);
}
