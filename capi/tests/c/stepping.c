/* foldsim's C library from C (docs/interop.md): every bad call answered with its error
 * code and a message, then a run stepped with inputs, every output printed as CSV.
 *
 *   cc -I include capi/tests/c/stepping.c -L target/release -lfoldsim_c \
 *      -Wl,-rpath,$PWD/target/release -o stepping
 *   ./stepping examples/paper-3panel.toml 200 0.01 > stepped.csv
 *
 * Inputs: hub_T_z = 0.5 N·m and hub_F_x = 1 N (hub frame) from the start, hub_T_z = -0.25
 * from half way. Exit status 0 when every check passed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "foldsim.h"

static int failures = 0;

/* A call must fail with `want`, and say something. */
static void expect(const char *what, FoldsimStatus got, FoldsimStatus want) {
    const char *message = foldsim_last_error();
    if (got != want || message == NULL || strlen(message) == 0) {
        fprintf(stderr, "FAIL %s: status %d (wanted %d), message \"%s\"\n", what, (int)got, (int)want,
                message ? message : "(null)");
        failures++;
    } else {
        fprintf(stderr, "ok   %s: %s\n", what, message);
    }
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s SCENARIO.toml STEPS DT\n", argv[0]);
        return 2;
    }
    const int steps = atoi(argv[2]);
    const double dt = atof(argv[3]);
    double x = 0.0;

    /* Bad calls: each returns its code and leaves a message. */
    if (foldsim_load_file(NULL) != NULL || strstr(foldsim_last_error(), "null") == NULL) {
        fprintf(stderr, "FAIL foldsim_load_file(NULL)\n");
        failures++;
    }
    if (foldsim_load_file("no/such/scenario.toml") != NULL || strstr(foldsim_last_error(), "scenario.toml") == NULL) {
        fprintf(stderr, "FAIL foldsim_load_file(missing file)\n");
        failures++;
    }
    if (foldsim_load_text("[run]\nduration = -1.0\n", NULL) != NULL || strlen(foldsim_last_error()) == 0) {
        fprintf(stderr, "FAIL foldsim_load_text(bad scenario)\n");
        failures++;
    }
    expect("advance(NULL)", foldsim_advance(NULL, 0.1), FOLDSIM_ERROR_NULL);

    FoldsimSimulation *sim = foldsim_load_file(argv[1]);
    if (sim == NULL) {
        fprintf(stderr, "FAIL load %s: %s\n", argv[1], foldsim_last_error());
        return 1;
    }
    expect("advance before start", foldsim_advance(sim, 0.1), FOLDSIM_ERROR_STATE);
    expect("get_output before start", foldsim_get_output(sim, "H_z", &x), FOLDSIM_ERROR_STATE);
    expect("set_parameter(run.duration)", foldsim_set_parameter(sim, "run.duration", 3.0), FOLDSIM_ERROR_ARGUMENT);
    expect("set_parameter(no such key)", foldsim_set_parameter(sim, "body.hub.nonsense", 3.0), FOLDSIM_ERROR_ARGUMENT);
    expect("set_parameter(negative mass)", foldsim_set_parameter(sim, "body.hub.mass", -1.0), FOLDSIM_ERROR_ARGUMENT);
    expect("set_parameter(NaN)", foldsim_set_parameter(sim, "body.hub.mass", NAN), FOLDSIM_ERROR_ARGUMENT);
    expect("set_input(wrong name)", foldsim_set_input(sim, "hub_T_w", 1.0), FOLDSIM_ERROR_ARGUMENT);
    expect("set_input(NaN)", foldsim_set_input(sim, "hub_T_z", NAN), FOLDSIM_ERROR_ARGUMENT);
    expect("set_input(inf)", foldsim_set_input(sim, "hub_T_z", INFINITY), FOLDSIM_ERROR_ARGUMENT);
    expect("set_input(NULL name)", foldsim_set_input(sim, NULL, 1.0), FOLDSIM_ERROR_NULL);
    expect("set_input_at(out of range)", foldsim_set_input_at(sim, 100000, 1.0), FOLDSIM_ERROR_ARGUMENT);

    /* The run. */
    if (foldsim_set_input(sim, "hub_T_z", 0.5) != FOLDSIM_OK || foldsim_set_input(sim, "hub_F_x", 1.0) != FOLDSIM_OK ||
        foldsim_start(sim) != FOLDSIM_OK) {
        fprintf(stderr, "FAIL start: %s\n", foldsim_last_error());
        return 1;
    }
    expect("start twice", foldsim_start(sim), FOLDSIM_ERROR_STATE);
    expect("set_parameter after start", foldsim_set_parameter(sim, "body.hub.mass", 2.0), FOLDSIM_ERROR_STATE);
    expect("advance(0)", foldsim_advance(sim, 0.0), FOLDSIM_ERROR_ARGUMENT);
    expect("advance(NaN)", foldsim_advance(sim, NAN), FOLDSIM_ERROR_ARGUMENT);
    expect("advance past the horizon", foldsim_advance(sim, 1e9), FOLDSIM_ERROR_RUN);
    expect("get_output(wrong name)", foldsim_get_output(sim, "H_w", &x), FOLDSIM_ERROR_ARGUMENT);
    expect("get_output(NULL value)", foldsim_get_output(sim, "H_z", NULL), FOLDSIM_ERROR_NULL);

    const size_t n = foldsim_output_count(sim);
    double *row = malloc(n * sizeof(double));
    expect("get_outputs(wrong count)", foldsim_get_outputs(sim, row, n + 1), FOLDSIM_ERROR_ARGUMENT);
    for (size_t j = 0; j < n; j++) printf(j ? ",%s" : "%s", foldsim_output_name(sim, j));
    printf("\n");
    for (int k = 0; k <= steps; k++) {
        if (foldsim_get_outputs(sim, row, n) != FOLDSIM_OK) {
            fprintf(stderr, "FAIL get_outputs: %s\n", foldsim_last_error());
            return 1;
        }
        for (size_t j = 0; j < n; j++) printf(j ? ",%.17g" : "%.17g", row[j]);
        printf("\n");
        if (k == steps) break;
        if (k == steps / 2 && foldsim_set_input(sim, "hub_T_z", -0.25) != FOLDSIM_OK) failures++;
        if (foldsim_advance(sim, dt) != FOLDSIM_OK) {
            fprintf(stderr, "FAIL advance at step %d: %s\n", k, foldsim_last_error());
            return 1;
        }
    }
    double t = 0.0, hz = 0.0;
    if (foldsim_time(sim, &t) != FOLDSIM_OK || fabs(t - steps * dt) > 1e-9 * (1.0 + t)) failures++;
    if (foldsim_get_output(sim, "H_z", &hz) != FOLDSIM_OK || !isfinite(hz)) failures++;
    free(row);
    foldsim_free(sim);
    foldsim_free(NULL);
    fprintf(stderr, "%s (%d failures), foldsim %s\n", failures ? "FAILED" : "passed", failures, foldsim_version());
    return failures ? 1 : 0;
}
