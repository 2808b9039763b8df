/*
 * Host timing program of the identification benchmark
 * (tools/bench/run_ident_bench.py): times pdt_identify in-process and
 * reports the workspace sizes. Not part of the library: stdio and malloc
 * are fine here.
 *
 *   pdt_ident_speed time FILE Ts fopdt|sopdt REPEATS
 *       FILE holds n little-endian doubles of u, then n of y (n from the
 *       file size). Prints one JSON line: n, evaluations, the median and
 *       the least wall time of REPEATS identifications (s), evaluations/s.
 *   pdt_ident_speed once FILE Ts fopdt|sopdt
 *       one identification (for callgrind); prints its evaluations, the
 *       coarse record's factor and the searches run.
 *   pdt_ident_speed workspace N
 *       pdt_ident_workspace_size for each model and criterion at N samples.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pdt/pdt.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int load(const char *path, pdt_real_t **u, pdt_real_t **y, size_t *n)
{
    FILE *f = fopen(path, "rb");
    long bytes;
    double *buf;
    size_t i, m;
    if (!f) {
        return -1;
    }
    fseek(f, 0, SEEK_END);
    bytes = ftell(f);
    fseek(f, 0, SEEK_SET);
    m = (size_t)bytes / sizeof(double);
    buf = malloc(m * sizeof(double));
    if (!buf || fread(buf, sizeof(double), m, f) != m || m % 2u != 0u) {
        fclose(f);
        free(buf);
        return -1;
    }
    fclose(f);
    *n = m / 2u;
    *u = malloc(*n * sizeof(pdt_real_t));
    *y = malloc(*n * sizeof(pdt_real_t));
    if (!*u || !*y) {
        free(buf);
        return -1;
    }
    for (i = 0; i < *n; i++) {
        (*u)[i] = (pdt_real_t)buf[i];
        (*y)[i] = (pdt_real_t)buf[*n + i];
    }
    free(buf);
    return 0;
}

static pdt_model_kind_t parse_model(const char *s)
{
    return strcmp(s, "sopdt") == 0 ? PDT_MODEL_SOPDT : PDT_MODEL_FOPDT;
}

static int identify(const pdt_ident_config_t *cfg, const pdt_ident_data_t *data, void *work,
                    size_t len, pdt_ident_result_t *res)
{
    pdt_ident_t ctx;
    pdt_status_t st = pdt_identify(&ctx, cfg, data, work, len, res);
    if (st != PDT_OK) {
        fprintf(stderr, "pdt_identify: %s\n", pdt_status_str(st));
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "workspace") == 0) {
        static const char *const costs[] = {"prediction", "simulation", "frequency", "combined"};
        size_t n = (size_t)strtoul(argv[2], NULL, 10);
        int m, c;
        printf("{\"n\":%zu,\"real_bytes\":%zu", n, sizeof(pdt_real_t));
        for (m = 1; m <= 2; m++) {
            for (c = 0; c < 4; c++) {
                pdt_ident_config_t cfg;
                pdt_ident_config_default(&cfg);
                cfg.model = (pdt_model_kind_t)m;
                cfg.cost = (pdt_cost_kind_t)c;
                cfg.Ts = (pdt_real_t)0.1;
                printf(",\"%s_%s\":%zu", m == 1 ? "fopdt" : "sopdt", costs[c],
                       pdt_ident_workspace_size(&cfg, n));
            }
        }
        printf(",\"ctx\":%zu}\n", sizeof(pdt_ident_t));
        return 0;
    }
    if (argc >= 5 && (strcmp(argv[1], "time") == 0 || strcmp(argv[1], "once") == 0)) {
        pdt_real_t *u = NULL, *y = NULL;
        size_t n, len;
        int reps = argc >= 6 ? atoi(argv[5]) : 1, r;
        pdt_ident_config_t cfg;
        pdt_ident_data_t data;
        pdt_ident_result_t res;
        void *work;
        double *t;
        if (load(argv[2], &u, &y, &n) != 0) {
            fprintf(stderr, "cannot read %s\n", argv[2]);
            return 2;
        }
        pdt_ident_config_default(&cfg);
        cfg.model = parse_model(argv[4]);
        cfg.Ts = (pdt_real_t)strtod(argv[3], NULL);
        data.u = u;
        data.y = y;
        data.n = n;
        len = pdt_ident_workspace_size(&cfg, n);
        work = malloc(len);
        if (reps < 1) {
            reps = 1;
        }
        t = malloc((size_t)reps * sizeof(double));
        if (!work || !t) {
            return 2;
        }
        if (strcmp(argv[1], "once") == 0) {
            if (identify(&cfg, &data, work, len, &res) != 0) {
                return 1;
            }
            printf("{\"n\":%zu,\"evaluations\":%u,\"coarse\":%u,\"searches\":%u}\n", n,
                   (unsigned)res.evaluations, (unsigned)res.coarse, (unsigned)res.searches);
            return 0;
        }
        for (r = 0; r < reps; r++) {
            double t0 = now_s();
            if (identify(&cfg, &data, work, len, &res) != 0) {
                return 1;
            }
            t[r] = now_s() - t0;
        }
        qsort(t, (size_t)reps, sizeof(double), cmp_double);
        printf("{\"n\":%zu,\"evaluations\":%u,\"median_s\":%.9g,\"min_s\":%.9g,"
               "\"evals_per_s\":%.9g,\"real_bytes\":%zu}\n",
               n, (unsigned)res.evaluations, t[reps / 2], t[0],
               (double)res.evaluations / t[reps / 2], sizeof(pdt_real_t));
        free(work);
        free(t);
        free(u);
        free(y);
        return 0;
    }
    fprintf(stderr, "usage: pdt_ident_speed time FILE Ts fopdt|sopdt REPEATS\n"
                    "       pdt_ident_speed once FILE Ts fopdt|sopdt\n"
                    "       pdt_ident_speed workspace N\n");
    return 2;
}
