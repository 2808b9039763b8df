// pdtfit autotune on a simulated heater: each loop() is one scan of the
// control task. The process is simulated in the sketch (a first-order lag
// with dead time), so the example runs on any 32-bit board without wiring;
// replace readProcess() and writeOutput() with your sensor and actuator.
#include <pdtfit.h>

#if defined(__AVR__)
#error "this example's record (300 samples, both model orders, validated) needs a 32-bit board: on an Arduino Mega 2560 use AutotuneMega"
#endif

static const float SCAN_S = 0.5f;      // control period, s
static const size_t CAPACITY = 300u;   // samples recorded: 150 s

// The autotune's workspace: the identification's bound for CAPACITY samples
// plus the record, checked against the exact size query in setup().
static pdt_real_t work[PDT_IDENT_WORKSPACE_SIZE(300u, PDT_IDENT_POPULATION_SOPDT) /
                           sizeof(pdt_real_t) + 2u * 300u + 1u];
static pdt_autotune_t tuner;
static bool running = false;

// The simulated heater: 2 degC per % with a 20 s lag and 3 s dead time,
// 20 degC ambient, starting at rest with the heater at 30 %.
static float heaterDelay[6];
static float temperature = 80.0f;
static float heater = 30.0f;

static float readProcess() { return temperature; }

static void writeOutput(float percent)
{
    const float tau = 20.0f, gain = 2.0f, ambient = 20.0f;
    float delayed = heaterDelay[0];
    for (unsigned i = 0; i + 1u < 6u; i++) {
        heaterDelay[i] = heaterDelay[i + 1u];
    }
    heaterDelay[5] = percent;
    temperature += (ambient + gain * delayed - temperature) * (SCAN_S / tau);
    heater = percent;
}

void setup()
{
    Serial.begin(115200);
    for (unsigned i = 0; i < 6u; i++) {
        heaterDelay[i] = heater;
    }
    pdt_autotune_config_t cfg;
    pdt_autotune_config_default(&cfg);
    cfg.Ts = SCAN_S;
    cfg.decimation = 1u;
    cfg.capacity = CAPACITY;
    cfg.settle = 10u;
    cfg.excite.kind = PDT_EXCITE_PRBS;
    cfg.excite.amplitude = 5.0f;
    cfg.excite.prbs_bits = 6u;
    cfg.excite.prbs_hold = 4u;
    cfg.u_min = 0.0f;
    cfg.u_max = 100.0f;
    cfg.pv_min = 20.0f;
    cfg.pv_max = 150.0f;
    cfg.max_scans = 1000u;
    size_t need = pdt_autotune_workspace_size(&cfg);
    if (need == 0u || need > sizeof work ||
        pdt_autotune_init(&tuner, &cfg, heater, work, need) != PDT_OK) {
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
    pdt_autotune_result_t res;
    (void)pdt_autotune_result(&tuner, &res);
    if (st != PDT_OK) {
        Serial.print("pdtfit: no gains: ");
        Serial.println(pdt_status_str(st));
        return;
    }
    Serial.print("Kc = ");
    Serial.println(res.tune.ideal.Kc);
    Serial.print("tauI = ");
    Serial.println(res.tune.ideal.tauI);
}
