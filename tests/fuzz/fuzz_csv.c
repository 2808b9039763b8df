/*
 * Fuzz target: the command line's reader of exports (tools/cli/csv.h) on
 * fuzzed text and options. Contracts checked: 0 with a series of n >= 1
 * finite values within max_abs (y may be NaN, a missing sample, in the
 * default reading) and a finite Ts >= 0 (0: the file gives no
 * period, the caller asks for one), or nonzero with an
 * empty series and a message that fits err (NUL-terminated, one line); no
 * leak (ASan's leak check). The first two bytes pick the options (bound on
 * the cells, separator, decimal mark, time unit, resampling, missing
 * samples refused or not, declared bad values), the rest is
 * the file.
 */
#include "csv.h"
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const double limits[] = {3.4028234663852886e38, 1.7976931348623157e308, 1e6, 1.0};
    static const char seps[] = {0, ',', ';', '\t'};
    if (size < 2u) {
        return 0;
    }
    pdtcli_csv_opts_t o;
    pdtcli_csv_opts_default(&o);
    o.max_abs = limits[data[0] % 4u];
    o.sep = seps[(data[0] >> 2) % 4u];
    o.decimal = (data[0] & 0x10u) ? ',' : 0;
    o.time_unit = (int)(data[1] % 6u) - 1; /* PDTCLI_TIME_AUTO .. _H */
    o.resample = (data[1] >> 2) & 1;
    o.bad_rows = (data[1] >> 3) & 1;
    static const double bad[] = {-9999.0, 32767.0};
    o.bad_values = bad;
    o.n_bad_values = (data[1] >> 4) & 1 ? 2u : 0u;
    pdtcli_series_t s;
    memset(&s, 0x5A, sizeof s);
    char err[96];
    memset(err, 'x', sizeof err);
    int rc = pdtcli_csv_parse_series((const char *)data + 2, size - 2u, &o, &s, err, sizeof err);
    if (rc == 0) {
        FZ_CHECK(s.u != NULL && s.y != NULL && s.n >= 1u);
        FZ_CHECK(isfinite(s.Ts) && s.Ts >= 0.0);
        for (size_t i = 0; i < s.n; i++) {
            FZ_CHECK(isfinite(s.u[i]) && fabs(s.u[i]) <= o.max_abs);
            /* A missing y is NaN, in the default reading only. */
            FZ_CHECK((isfinite(s.y[i]) && fabs(s.y[i]) <= o.max_abs) ||
                     (isnan(s.y[i]) && o.bad_rows == PDTCLI_BAD_ROWS_MISSING));
        }
    } else {
        FZ_CHECK(s.n == 0u && s.u == NULL && s.y == NULL);
        FZ_CHECK(memchr(err, '\0', sizeof err) != NULL);
        FZ_CHECK(strchr(err, '\n') == NULL);
    }
    pdtcli_series_free(&s);
    return 0;
}
