/*
 * pdtfit identify, shared between its sources: the options, the record,
 * the result, and the outputs beside the JSON (--out-sim, --plot).
 */
#ifndef PDTCLI_IDENTIFY_H
#define PDTCLI_IDENTIFY_H

#include "csv.h"
#include "tune_opts.h"

#if PDT_IDENT_MAX_RECORDS < 2
#error "pdtfit identify reads several records: build it with PDT_IDENT_MAX_RECORDS 2 .. 8"
#endif

enum { METHOD_GA, METHOD_ELMS, METHOD_EIV };
enum { UNC_AUTO, UNC_FISHER, UNC_BOOTSTRAP };

typedef struct ident_args {
    int model, method, cost, weight, offset, initial, integer_delay, time_unit, resample;
    int bad_rows, force, drift;
    cli_list_t bad_values;
    int units_row;      /* --units-row */
    int uncertainty;    /* --uncertainty: UNC_AUTO, UNC_FISHER, UNC_BOOTSTRAP */
    uint64_t boot_runs; /* --bootstrap N */
    int have_boot_runs;
    const char *time_format; /* --time-format */
    double td_max, fs, phi_t, phi_f, f_lo, f_hi, u_before;
    uint64_t seed, evaluations, population, coarse, skip;
    const char *band, *t_col, *u_col, *y_col, *sep, *decimal, *file;
    /* Further records of the same process (FILE ...), after file. */
    const char *more[PDT_IDENT_MAX_RECORDS - 1u];
    size_t n_more;
    int have_initial;
    const char *out_sim, *plot, *plot_script, *tune;
    int have_model, have_td_max, have_fs, have_evaluations, have_population, have_weight;
    int have_phi_t, have_phi_f, have_time_unit, have_u_before;
    tune_opts_t t;
} ident_args_t;

/* The record in the library's real type. */
typedef struct ident_data {
    pdtcli_series_t s;
    pdt_real_t *u, *y;
} ident_data_t;

/* The fit of a model as pdt_ident reports it, with its simulated output
 * into ysim (n values; may be NULL): the model discretised exactly and run
 * from rest on u - u0, plus y0. NaN when it cannot be simulated. */
/* Adds to ysim (n values) the result's estimated free response from the
 * first sample and its drift, where it has them. */
void ident_add_state(const pdt_ident_result_t *r, double Ts, size_t n, double *ysim);
double ident_simulate(const pdt_model_t *m, double Ts, const ident_data_t *d, pdt_real_t u0,
                      pdt_real_t y0, double *ysim);

/* Reads the record of path (a CSV file, or - for stdin) with a's column
 * options, with the reader's warnings; ends the program on an error. */
void ident_read(const ident_args_t *a, const char *path, ident_data_t *d);
/* The identification's configuration of a's options at period Ts. */
void ident_ga_config(const ident_args_t *a, double Ts, pdt_ident_config_t *cfg);
/* Several records (a->n_more > 0): identified together, printed; the
 * exit status. */
int ident_several(const ident_args_t *a);

/* Writes t,u,y,ysim,residual of the record and the model to path. */
void ident_write_sim(const char *path, const ident_data_t *d, const pdt_ident_result_t *r);
/* Draws the record against the model into png with the Python script. */
void ident_plot(const ident_args_t *a, const ident_data_t *d, const pdt_ident_result_t *r);

#endif /* PDTCLI_IDENTIFY_H */
