/*
 * pdt_fb_autotune: an IEC 61131-3-style function block over pdtfit's
 * autotune (pdt/pdt_autotune.h) and the PID that runs its gains
 * (pdt/pdt_pid.h), for PLC runtimes that call C function blocks, and for
 * MCU firmware written in the same style.
 *
 * The instance struct is the function block: its fields are, in order,
 * the VAR_INPUT, VAR_OUTPUT and VAR sections of the Structured Text
 * declaration in AutotuneFB.st, with the IEC types mapped as
 *   BOOL -> bool (one byte), INT -> int16_t, UDINT -> uint32_t,
 *   REAL -> pdt_real_t (float: the default build; a double build maps to
 *   LREAL), STRING(39) -> char[40] (NUL-terminated).
 * The internal part (the autotune and its workspace) is one opaque member,
 * so the declaration only has to reserve its size.
 *
 * Use, once per task cycle, from the same task (the block is not
 * reentrant and keeps no global state):
 *
 *   static pdt_fb_autotune_t fbTune;        // instance: static, not stack
 *   pdt_fb_autotune_init(&fbTune);          // once: the declared defaults
 *   ...every cycle:
 *   fbTune.rPV = read_pv();
 *   fbTune.rOutputNow = output_in_service;
 *   fbTune.xExecute = start_button;
 *   fbTune.xAuto = auto_requested;          // PID once gains exist
 *   fbTune.rSetpoint = setpoint;
 *   (void)pdt_fb_autotune(&fbTune);
 *   if (fbTune.xBusy || fbTune.xAutoActive) write_output(fbTune.rOutput);
 *   else write_output(manual_output);       // and rOutputNow = it
 *
 * Behaviour (PLCopen conventions; docs/plc.md has the cycle-by-cycle
 * detail):
 *  - A rising edge of xExecute latches the parameters, takes rOutputNow as
 *    the operating point (the process must be at rest there) and starts:
 *    xBusy is TRUE from that same cycle, and rOutput is the output to
 *    apply. Parameters changed while busy take effect at the next start.
 *    A rising edge while busy is ignored.
 *  - Exactly one of xDone, xError, xCommandAborted ends a command. It stays
 *    TRUE while xExecute is TRUE and clears with xExecute; if xExecute is
 *    already FALSE when the command ends, it is TRUE for exactly one cycle.
 *    The falling edge of xExecute does not stop a running autotune.
 *  - A rising edge of xAbort while busy stops at once: rOutput returns to
 *    the operating point, xCommandAborted. A start while xAbort is TRUE is
 *    refused the same way.
 *  - iErrorID is the pdt_status_t that ended the command (0 unless
 *    xError): a refused start (bad parameter: PDT_ERR_ARG, ...), a safety
 *    abort (PDT_ERR_PV_LIMIT, PDT_ERR_TIMEOUT, ...), data that could not
 *    support a model, or refused gains (PDT_ERR_POOR_FIT,
 *    PDT_ERR_MS_LIMIT, PDT_ERR_UNSTABLE; the model outputs are still
 *    valid then).
 *  - rOutput: rOutputNow before the first start and after a refused start;
 *    the experiment while busy; the operating point once the command has
 *    ended, held until the next start.
 *  - The PID (docs/pid.md): when a command ends with Done, the block
 *    loads the gains into its PID, starting from the operating point.
 *    While xAuto is TRUE, gains are valid and no autotune runs, the PID
 *    drives rOutput (xAutoActive), with rSetpoint as its set-point. While
 *    xAuto is FALSE the PID tracks rOutputNow, so that switching xAuto on
 *    continues from the output in service without a bump; the PID
 *    parameters are taken at Done and on every rising edge of xAuto (a
 *    bumpless change). Switching xAuto off leaves rOutput at the last PID
 *    output. A new start clears the gains and the PID until its Done. A
 *    NaN or infinite pv in automatic holds rOutput (iPidStatus
 *    PDT_ERR_NONFINITE).
 *  - The running autotune keeps pointers into the instance. An instance
 *    moved while busy (e.g. by a runtime's online change) is detected on
 *    its next cycle: it ends with PDT_ERR_STATE and rOutput = the output at
 *    the start, without touching the stale pointers. An idle instance may
 *    be moved freely.
 *
 * Time and memory per cycle: see docs/plc.md. The instance holds the
 * record and the identification's workspace for PDT_FB_AUTOTUNE_CAPACITY
 * samples, sized at compile time.
 */
#ifndef PDT_FB_AUTOTUNE_H
#define PDT_FB_AUTOTUNE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pdt/pdt_autotune.h"
#include "pdt/pdt_pid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most identification samples one instance can record (udiSamples up to
 * this); sizes the instance. Override on the compiler command line. */
#ifndef PDT_FB_AUTOTUNE_CAPACITY
#define PDT_FB_AUTOTUNE_CAPACITY 400u
#endif

/* Workspace reals in one instance: enough for any configuration and the
 * automatic population of either model. */
#define PDT_FB_AUTOTUNE_WORK_REALS                                                                 \
    ((PDT_AUTOTUNE_WORKSPACE_SIZE(PDT_FB_AUTOTUNE_CAPACITY, PDT_IDENT_POPULATION_SOPDT) +          \
      sizeof(pdt_real_t) - 1u) /                                                                   \
     sizeof(pdt_real_t))

/* iModel: both models identified and the order the data support kept
 * (the autotune's order_auto, its default). */
#define PDT_FB_AUTOTUNE_MODEL_AUTO 0

/* Length of sStatus, terminating NUL included: STRING(39). */
#define PDT_FB_AUTOTUNE_STATUS_LEN 40u

/* The internal VARs. Private: the ST declaration reserves its size only. */
typedef struct pdt_fb_autotune_internal {
    bool xExecutePrev;                           /* xExecute of the last cycle (edge memory) */
    bool xAbortPrev;                             /* xAbort of the last cycle */
    pdt_real_t rStartOutput;                     /* rOutputNow at the start */
    bool xAutoPrev;                              /* xAuto of the last cycle */
    bool xPidReady;                              /* pid holds the last Done's gains */
    const void *self;                            /* the instance's address at the start: the
                               * autotune points into the instance */
    pdt_pid_t pid;                               /* the PID with the tuned gains */
    pdt_autotune_t at;                           /* the autotune, valid while xBusy and after */
    pdt_real_t work[PDT_FB_AUTOTUNE_WORK_REALS]; /* its workspace */
} pdt_fb_autotune_internal_t;

typedef struct pdt_fb_autotune {
    /* VAR_INPUT: commands and process signals, read every cycle. */
    bool xExecute;         /* rising edge: start an autotune */
    bool xAbort;           /* rising edge: stop it (safe output) */
    bool xAuto;            /* TRUE: the PID drives rOutput once there
                               * are gains (automatic); FALSE: manual */
    pdt_real_t rPV;        /* process value read this cycle, pv units */
    pdt_real_t rSetpoint;  /* the PID's set-point, and the pv the relay
                               * experiment switches around, pv units */
    pdt_real_t rOutputNow; /* output in service, output units: the
                               * operating point at the start, rOutput
                               * before the first start, and what the PID
                               * tracks in manual */
    /* VAR_INPUT: parameters, latched at the start (initial values are set
     * by pdt_fb_autotune_init). */
    pdt_real_t rScanPeriod;   /* s between two calls (the task cycle), > 0.
                               * Init 0.1 */
    uint32_t udiDecimation;   /* cycles per identification sample; 0 = 1.
                               * Init 1 */
    uint32_t udiSamples;      /* identification samples recorded, settle
                               * included; 0 = PDT_FB_AUTOTUNE_CAPACITY.
                               * Init 0 */
    uint32_t udiSettle;       /* of those, samples at the operating point
                               * before the experiment; 0 = 20. Init 0 */
    uint32_t udiEvalsPerScan; /* identification work per cycle (cost
                               * evaluations); 0 = 4. Init 0 */
    int16_t iExperiment;      /* pdt_excite_kind_t: 1 step, 2 pulse,
                               * 3 chirp, 4 PRBS(7), 5 relay. Init 1 */
    int16_t iModel;           /* 0 (PDT_FB_AUTOTUNE_MODEL_AUTO): FOPDT and
                               * SOPDT, the data choose; else the
                               * pdt_model_kind_t fixed: 1 FOPDT, 2 SOPDT.
                               * Init 0 */
    pdt_real_t rAmplitude;    /* output units: step or pulse change (either
                               * sign), chirp or PRBS half swing, relay
                               * half swing d. Init 5 */
    pdt_real_t rExciteTime;   /* s: step duration (0: to the end of the
                               * record), pulse width (and the rest after
                               * it), chirp sweep time, PRBS chip time
                               * (0: one cycle); unused by the relay.
                               * Init 0 */
    pdt_real_t rFrequency;    /* chirp: end frequency, Hz (from 0). Init 0 */
    pdt_real_t rHysteresis;   /* relay: band around rSetpoint, pv units,
                               * >= 0. Init 0 */
    pdt_real_t rOutMin;       /* output limits, output units. Init 0 */
    pdt_real_t rOutMax;       /* Init 100 */
    pdt_real_t rPvMin;        /* process value limits, pv units: leaving */
    pdt_real_t rPvMax;        /* them ends the autotune. Init -1e30, 1e30 */
    pdt_real_t rTimeLimit;    /* s for the experiment (settle included);
                               * 0: none. Init 0 */
    int16_t iRule;            /* pdt_tune_rule_t: 0 SIMC, 1 IMC, 2 AMIGO,
                               * 3 Ziegler-Nichols. Init 0 */
    int16_t iForm;            /* pdt_tune_form_t: 0 PI, 1 PID. Init 0 */
    pdt_real_t rFitMin;       /* refuse gains below this fit, %; 0: the
                               * evidence decides alone. Init 0 */
    pdt_real_t rMsMax;        /* refuse gains above this Ms; 0: no limit,
                               * else > 1. Init 2 */
    /* VAR_INPUT: PID parameters, taken at Done and on a rising edge of
     * xAuto (the PID also uses rScanPeriod, rOutMin, rOutMax). */
    pdt_real_t rSpWeightP; /* set-point weight b of the P term, >= 0.
                               * Init 1 */
    pdt_real_t rSpWeightD; /* set-point weight c of the D term, >= 0;
                               * 0: derivative on the measurement. Init 0 */
    pdt_real_t rRateMax;   /* output units per s, 0: no limit. Init 0 */
    pdt_real_t rTrackTime; /* anti-windup tracking time Tt, s; 0: the
                               * default rule. Init 0 */
    int16_t iAntiWindup;   /* pdt_pid_antiwindup_t: 0 back-calculation,
                               * 1 conditional, 2 both, 3 none. Init 0 */

    /* VAR_OUTPUT */
    pdt_real_t rOutput;                       /* output to apply this cycle, output units */
    bool xBusy;                               /* an autotune runs: apply rOutput */
    bool xDone;                               /* model and gains ready */
    bool xError;                              /* ended by iErrorID */
    bool xCommandAborted;                     /* ended by xAbort */
    int16_t iErrorID;                         /* pdt_status_t that ended it, 0 if none */
    int16_t iPhase;                           /* pdt_autotune_phase_t: 0 never started (or
                               * refused), 1 settle, 2 excite, 3 identify,
                               * 4 tune, 5 done, 6 failed */
    char sStatus[PDT_FB_AUTOTUNE_STATUS_LEN]; /* the state, in words */
    bool xModelValid;                         /* the model outputs hold the last model */
    bool xGainsValid;                         /* the gain outputs hold the last gains */
    bool xIntegrating;                        /* the model is an integrator with a lag */
    pdt_real_t rGain;                         /* DC gain, pv units per output unit; an
                               * integrator's gain per second */
    pdt_real_t rTau1;                         /* FOPDT time constant; SOPDT larger time
                               * constant (complex pair: 1 / wn); an
                               * integrator's lag, s */
    pdt_real_t rTau2;                         /* SOPDT smaller time constant (complex
                               * pair: 1 / wn), s; 0 otherwise */
    pdt_real_t rZeta;                         /* SOPDT damping ratio; 0 otherwise */
    pdt_real_t rDeadTime;                     /* s */
    pdt_real_t rFit;                          /* fit of the model to the record, % */
    pdt_real_t rKc;                           /* ideal form Kc (1 + 1/(Ti s) + Td s/(Tf s + 1)): */
    pdt_real_t rTi;                           /* output units per pv unit, s, s, s; the sign */
    pdt_real_t rTd;                           /* of rKc is the controller's action (negative: */
    pdt_real_t rTf;                           /* direct acting) */
    pdt_real_t rMs;                           /* maximum sensitivity of the loop with the model */
    bool xAutoActive;                         /* the PID drives rOutput this cycle */
    bool xLimited;                            /* the PID's output is at a limit (range,
                               * rate) */
    int16_t iPidStatus;                       /* pdt_status_t of the PID's last call: 0, or
                               * e.g. PDT_ERR_NONFINITE (pv failed, output
                               * held), PDT_ERR_ARG (a PID parameter) */

    /* VAR */
    pdt_fb_autotune_internal_t internal;
} pdt_fb_autotune_t;

/* Sets every field of fb to the initial values of the ST declaration
 * (inputs, parameters, cleared outputs, "idle"), as a PLC does for a new
 * instance. Call once before the first cycle, and never while busy.
 * Nothing for NULL. O(1) plus clearing the instance. */
void pdt_fb_autotune_init(pdt_fb_autotune_t *fb);

/* One task cycle: reads the inputs, acts on edges, advances a running
 * autotune by one scan or runs (or tracks) the PID, writes the outputs
 * (see the top of this file).
 * Returns PDT_ERR_ARG for NULL (nothing written), else PDT_OK: the
 * outcome of the command is in the outputs, not in the return value.
 * Work: one pdt_autotune_scan (see pdt_autotune.h), plus on a start one
 * pdt_autotune_init (O(1)); when idle, one pdt_pid_update or
 * pdt_pid_track (O(1)). */
pdt_status_t pdt_fb_autotune(pdt_fb_autotune_t *fb);

/* Entry points for a PLC runtime's external-function glue, where the
 * instance is memory the PLC declared (AutotuneFB.st, PDT_FB_AUTOTUNE_T):
 * size is the PLC's SIZEOF of it, checked against sizeof(pdt_fb_autotune_t)
 * so that a declaration out of step with this header is refused instead of
 * misread. Return PDT_ERR_ARG (nothing done) for NULL, a size that differs,
 * or block not aligned for the struct; else as pdt_fb_autotune_init (then
 * PDT_OK) and pdt_fb_autotune. */
pdt_status_t pdt_fb_autotune_ext_init(void *block, uint32_t size);
pdt_status_t pdt_fb_autotune_ext_cycle(void *block, uint32_t size);

#ifdef __cplusplus
}
#endif

#endif /* PDT_FB_AUTOTUNE_H */
