/*
 * Fuzz target: the command line's CSV reader (tools/cli/csv.h) on fuzzed
 * file contents. Contracts checked: 0 with a table whose columns hold only
 * finite values within max_abs, or -1 with an empty table and a message
 * that fits err (NUL-terminated, one line); no leak (ASan's leak check).
 * The first byte picks max_abs, the rest is the file.
 */
#define _GNU_SOURCE /* fmemopen */
#include "csv.h"
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const double limits[] = {3.4028234663852886e38, 1.7976931348623157e308, 1e6, 1.0};
    if (size == 0u) {
        return 0;
    }
    double max_abs = limits[data[0] % 4u];
    FILE *in = fmemopen((void *)(data + 1), size - 1u, "r");
    if (in == NULL) {
        return 0; /* fmemopen refuses an empty buffer on some libcs */
    }
    csv_table_t t;
    memset(&t, 0x5A, sizeof t);
    char err[96];
    memset(err, 'x', sizeof err);
    int rc = csv_read_tuy(in, "fuzz.csv", max_abs, &t, err, sizeof err);
    fclose(in);
    if (rc == 0) {
        FZ_CHECK(t.u != NULL && t.y != NULL);
        for (size_t i = 0; i < t.rows; i++) {
            FZ_CHECK(isfinite(t.u[i]) && fabs(t.u[i]) <= max_abs);
            FZ_CHECK(isfinite(t.y[i]) && fabs(t.y[i]) <= max_abs);
            if (t.t != NULL) {
                FZ_CHECK(isfinite(t.t[i]) && fabs(t.t[i]) <= max_abs);
            }
        }
    } else {
        FZ_CHECK(rc == -1);
        FZ_CHECK(t.rows == 0u && t.t == NULL && t.u == NULL && t.y == NULL);
        FZ_CHECK(memchr(err, '\0', sizeof err) != NULL);
        FZ_CHECK(strchr(err, '\n') == NULL);
    }
    csv_table_free(&t);
    return 0;
}
