// pdtfit autotune on an Arduino Mega 2560 (ATmega2560, 8 KiB of RAM), on a
// heater simulated in the sketch: each loop() is one scan of the control
// task. It is the configuration the AVR target test runs under simavr
// (tests/target/avr): a record of 50 samples at 1 s, the model order fixed
// to a FOPDT and no validation, which is what 8 KiB hold beside the 3 KiB
// autotune object and the 1.5 KiB of stack its scans take, with room for
// the core's own. The tuning's scan takes about 1.4 s at 16 MHz
// (docs/port.md). Replace readProcess()
// and writeOutput() with your sensor and actuator.
#include <pdtfit.h>

#if defined(__AVR__)
#include <avr/io.h>
#if (RAMEND - RAMSTART + 1) < 8192
#error "pdtfit's autotune needs 8 KiB of RAM (ATmega2560, Arduino Mega 2560); this board has less: its PID (pdt_pid_update) fits"
#endif
#endif

static const float SCAN_S = 1.0f;   // control period, s
static const size_t CAPACITY = 50u; // samples recorded: 50 s

// The workspace: the record (2 reals a sample) and the FOPDT
// identification's (3 reals a sample and 11 per individual), checked
// against the exact size query in setup(). Once the run is over the
// library no longer uses it, and the result (500 bytes, which the stack
// could not spare) is copied there.
static union {
    pdt_real_t work[5u * 50u + 11u * PDT_IDENT_POPULATION_FOPDT];
    pdt_autotune_result_t res;
} mem;
static pdt_autotune_t tuner;
static bool running = false;

// The simulated heater: 2 degC per % with a 10 s lag and 3 s dead time,
// 20 degC ambient, starting at rest with the heater at 30 %.
static float heaterDelay[3];
static float temperature = 80.0f;

static float readProcess() { return temperature; }

static void writeOutput(float percent)
{
    const float tau = 10.0f, gain = 2.0f, ambient = 20.0f;
    float delayed = heaterDelay[0];
    heaterDelay[0] = heaterDelay[1];
    heaterDelay[1] = heaterDelay[2];
    heaterDelay[2] = percent;
    temperature += (ambient + gain * delayed - temperature) * (SCAN_S / tau);
}

void setup()
{
    Serial.begin(115200);
    for (unsigned i = 0; i < 3u; i++) {
        heaterDelay[i] = 30.0f;
    }
    pdt_autotune_config_t cfg;
    pdt_autotune_config_default(&cfg);
    cfg.Ts = SCAN_S;
    cfg.capacity = CAPACITY;
    cfg.settle = 10u;
    cfg.excite.kind = PDT_EXCITE_PRBS;
    cfg.excite.amplitude = 5.0f;
    cfg.excite.prbs_bits = 4u;
    cfg.excite.prbs_hold = 2u;
    cfg.u_min = 0.0f;
    cfg.u_max = 100.0f;
    cfg.pv_min = 20.0f;
    cfg.pv_max = 150.0f;
    cfg.max_scans = 1000u;
    cfg.ident.model = PDT_MODEL_FOPDT;
    // No screen for gross errors and missing samples refused: the
    // workspace then holds no copy of the record, which 8 KiB cannot spare.
    cfg.ident.no_screen = true;
    cfg.ident.refuse_missing = true;
    cfg.order_auto = false;
    cfg.ms_robust = 0.0f;
    size_t need = pdt_autotune_workspace_size(&cfg);
    if (need == 0u || need > sizeof mem.work ||
        pdt_autotune_init(&tuner, &cfg, 30.0f, mem.work, need) != PDT_OK) {
        Serial.println("pdtfit: configuration refused");
        return;
    }
    running = true;
}

void loop()
{
    if (!running) {
        return;
    }
    float u;
    pdt_status_t st = pdt_autotune_scan(&tuner, readProcess(), &u);
    writeOutput(u); // always apply it, also after a refusal
    if (st == PDT_RUNNING) {
        delay((unsigned long)(SCAN_S * 1000.0f));
        return;
    }
    running = false;
    if (st != PDT_OK) {
        Serial.print("pdtfit: no gains, status ");
        Serial.println((double)st);
        return;
    }
    (void)pdt_autotune_result(&tuner, &mem.res);
    Serial.print("Kc = ");
    Serial.println(mem.res.tune.ideal.Kc);
    Serial.print("tauI = ");
    Serial.println(mem.res.tune.ideal.tauI);
}
