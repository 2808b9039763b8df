/*
 * The identification context's private parts, one per stage of the engine
 * (docs/ident-engine.md, docs/design.md). The caller allocates
 * pdt_ident_t, so their sizes must be visible to it, and this header is
 * installed; nothing in it is an interface. pdt/pdt_ident.h includes it:
 * include that header, not this one. The layout may change in any
 * release.
 */
#ifndef PDT_IDENT_STATE_H
#define PDT_IDENT_STATE_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_cost.h"
#include "pdt/pdt_model.h"

typedef struct pdt_ident_best {
    pdt_real_t genes[3]; /* the best candidate of the search so far */
    pdt_real_t cost;     /* normalised */
    pdt_real_t gain;
    pdt_real_t offset;
} pdt_ident_best_t;

typedef struct pdt_ident_ga {
    pdt_rng_t rng;
    uint32_t next; /* next individual to evaluate */
    uint32_t stall;
    uint32_t resolved;       /* generations in a row with one niche left */
    pdt_real_t best_history; /* best cost at the last stall check */
    pdt_real_t *pop;         /* P x genes, then P costs, gains, offsets */
    pdt_real_t *pop_cost;
    pdt_real_t *pop_gain;
    pdt_real_t *pop_offset;
    pdt_real_t *off; /* offspring, the same layout */
    pdt_real_t *off_cost;
    pdt_real_t *off_gain;
    pdt_real_t *off_offset;
    pdt_real_t *shared; /* P shared costs */
} pdt_ident_ga_t;

typedef struct pdt_ident_simplex {
    pdt_real_t x[4][3]; /* at most 3 genes, 4 vertices */
    pdt_real_t f[4];
    pdt_real_t trial[3];
    pdt_real_t trial2[3];
    pdt_real_t ftrial;
    uint32_t state;
    uint32_t index;
    uint32_t budget;
} pdt_ident_simplex_t;

typedef struct pdt_ident_polish {
    pdt_real_t x[3];     /* the centre */
    pdt_real_t f0;       /* its cost */
    pdt_real_t w[3];     /* each gene's difference step, normalised */
    pdt_real_t f[12];    /* the costs about the centre */
    pdt_real_t trial[3]; /* the Newton step's point */
    pdt_real_t len;      /* its distance, normalised */
    pdt_real_t pred;     /* the cost's decrease the model expects there */
    uint32_t state;
    uint32_t next; /* next point about the centre */
    uint32_t iter; /* Newton steps taken */
    uint32_t back; /* halvings of the running step */
    uint32_t dims; /* genes moved: all, or all but the dead time pinned */
    bool cut;      /* the running step was cut to its reach */
    bool rose;     /* a try of it raised the cost beyond rounding */
    bool fine;     /* narrow differences: a whole step succeeded or the
                    * centre stood */
} pdt_ident_polish_t;

typedef struct pdt_ident_refine {
    pdt_ident_simplex_t run0; /* niche run 0; Nelder-Mead's polish of the best */
    /* Niche runs 1 and 2 end before a Newton polish begins, and a polish
     * hands over to Nelder-Mead in run0 only: they share storage. */
    union {
        pdt_ident_simplex_t more[2]; /* niche runs 1 and 2 */
        pdt_ident_polish_t polish;   /* the Newton polish */
    } late;
    pdt_real_t starts[3][3]; /* the best of up to 3 niches */
    uint32_t nstarts;
    uint32_t start_i;      /* nstarts: the final polish of the best */
    uint32_t next;         /* the niche run whose point comes next */
    pdt_real_t r;          /* that polish's dead time, samples */
    pdt_real_t f_kink;     /* the pinned pass's least cost */
    bool near;             /* its dead time's differences reached a kink */
    bool keep_probe;       /* a polish of the dead-time profile's: its
                            * Nelder-Mead keeps the probe's share back */
    uint32_t probe;        /* the dead-time probe's next point, from 1 */
    pdt_real_t probe_x[3]; /* its centre: the answer polished */
    pdt_real_t probe_f;    /* and its cost */
} pdt_ident_refine_t;

typedef struct pdt_ident_scan {
    pdt_cost_t cost_time; /* the time cost the dead time is scanned on */
    uint32_t i;
    pdt_real_t step, best, td, gain, offset;
    pdt_real_t a, b, x1, x2, f1, f2; /* golden section */
} pdt_ident_scan_t;

/* The answers kept: one per independent search and the dead-time
 * profile's polish (pdt_ident.h derives PDT_IDENT_MAX_SEARCHES from it). */
#define PDT_IDENT_VOTES 4u

typedef struct pdt_ident_vote {
    uint32_t searches; /* to run */
    uint32_t done;     /* answers kept: the searches finished, the profile's */
    uint32_t budget;   /* evaluations of each */
    uint32_t base;     /* evaluations before the running one */
    uint32_t profiled; /* 1 + the index of the profile's answer, 0: none */
    pdt_model_t found[PDT_IDENT_VOTES];
    pdt_real_t cost[PDT_IDENT_VOTES]; /* normalised */
    pdt_real_t y0[PDT_IDENT_VOTES];
    pdt_real_t fit[PDT_IDENT_VOTES];
    pdt_real_t genes[PDT_IDENT_VOTES][3];
} pdt_ident_vote_t;

typedef struct pdt_ident_profile {
    uint32_t next;       /* next grid point: dead-time index * shapes + shape */
    uint32_t points;     /* dead times on the grid over the whole range */
    uint32_t fine;       /* dead times of the window about the answer, 0: none */
    pdt_real_t td0;      /* the grid's first, s */
    pdt_real_t step;     /* between its points, s */
    pdt_real_t fine_td0; /* the window's first, s; one sample apart */
    pdt_real_t td;       /* the answer's dead time, s */
    /* [0] of the grid's points, near: within PROFILE_NEAR steps of td;
     * [1] of the window's, near: within PROFILE_NEAR samples. */
    pdt_real_t near[2]; /* least cost near td */
    pdt_real_t far[2];  /* least cost beyond, at far_x */
    pdt_real_t far_x[2][3];
    pdt_real_t bounds[2]; /* the dead-time gene's, while the search across
                           * the kink narrows them */
} pdt_ident_profile_t;

typedef struct pdt_ident_coarse {
    uint32_t factor;    /* D of the searches' record, 1: the whole */
    uint32_t delay_max; /* the whole record's cost's */
    bool whole;         /* the coarse answer's polish on the whole record
                         * runs (Nelder-Mead's smaller steps) */
} pdt_ident_coarse_t;

typedef struct pdt_ident_screen {
    pdt_real_t *yfill;      /* n reals of the workspace: y with the samples
                        * left out filled in */
    uint8_t *mask;          /* n bits of the workspace: the samples left out */
    uint8_t *fresh;         /* n bits of the workspace: those of this round */
    const pdt_real_t *y_in; /* the caller's y */
    void *work;             /* the whole workspace, for the next round */
    size_t work_len;
    size_t first;        /* the first sample left out; n when none */
    uint32_t excluded;   /* samples left out */
    uint32_t missing;    /* of them, not finite in the caller's y */
    uint32_t limit;      /* most that may be */
    uint32_t rounds;     /* identifications run again */
    uint32_t prior;      /* evaluations of the rounds before */
    bool settled;        /* the last round found nothing new */
    pdt_status_t status; /* PDT_ERR_OUTLIER beyond the limit, else PDT_OK */
} pdt_ident_screen_t;

#endif /* PDT_IDENT_STATE_H */
