/*
 * The stepping half of the C API (mbfx_simulation_*), run by capi/tests/c.rs:
 *   simulation_test PENDULUM.adm ROWS.txt CART_POLE.adm
 * PENDULUM.adm has a PINPUT torque TORQUE and a POUTPUT angle ANGLE; ROWS.txt holds the
 * rows `mbfx run` gives for it (GSTIFF, output step 0.02, probes angle = AZ(21, 10) and
 * wz = WZ(21, 10)): a line "ROWS COLUMNS", then each row's time and columns in shortest
 * round-trip decimal. Advancing to each row's time must give those columns bit for bit.
 * Then every error path, snapshots and reset; CART_POLE.adm fails at its first vertical
 * crossing (t = 0.4515 s) at the default HMIN of an output step of 0.1 s. Prints "N checks, M failed".
 */
#include "mbfx.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int checks = 0, failures = 0;

static void check(int ok, const char *what, int line) {
    ++checks;
    if (!ok) {
        ++failures;
        printf("FAILED (line %d): %s\n", line, what);
    }
}
#define CHECK(x) check((x), #x, __LINE__)

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The whole file at `path`, NUL-terminated (the caller frees it), or NULL. */
static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    char *text;
    long n;
    if (!f) return NULL;
    if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return NULL;
    }
    text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = '\0';
    fclose(f);
    return text;
}

static const char *PROBES[] = {"angle=AZ(21, 10)", "wz=WZ(21, 10)"};

static mbfx_simulation *pendulum(const char *text, mbfx_error **err) {
    return mbfx_simulation_new(text, "gstiff", 0.0, 0.02, PROBES, 2, NULL, 0, err);
}

/* Advancing to each of run's output times gives run's rows bit for bit. */
static void matches_run(const char *text, const char *rows_path) {
    mbfx_error *err = NULL;
    mbfx_simulation *sim = pendulum(text, &err);
    FILE *rows = fopen(rows_path, "r");
    size_t n_rows = 0, n_cols = 0, r, c, matched = 0;
    double out[3];
    CHECK(sim != NULL && err == NULL);
    CHECK(rows != NULL);
    if (!sim || !rows) {
        if (err) printf("%s", mbfx_error_report(err));
        mbfx_error_free(err);
        mbfx_simulation_free(sim);
        if (rows) fclose(rows);
        return;
    }
    CHECK(mbfx_simulation_output_count(sim) == 3);
    CHECK(strcmp(mbfx_simulation_output_name(sim, 0), "ANGLE") == 0);
    CHECK(strcmp(mbfx_simulation_output_name(sim, 1), "angle") == 0);
    CHECK(strcmp(mbfx_simulation_output_name(sim, 2), "wz") == 0);
    CHECK(mbfx_simulation_output_name(sim, 3) == NULL);
    CHECK(mbfx_simulation_input_count(sim) == 1);
    CHECK(strcmp(mbfx_simulation_input_name(sim, 0), "TORQUE") == 0);
    CHECK(mbfx_simulation_input_name(sim, 1) == NULL);
    CHECK(fscanf(rows, "%zu %zu", &n_rows, &n_cols) == 2 && n_cols == 3 && n_rows > 50);
    for (r = 0; r < n_rows; ++r) {
        double row[3];
        int ok = 1;
        for (c = 0; c < 3; ++c) ok &= fscanf(rows, "%lf", &row[c]) == 1;
        if (!ok) break;
        if (r > 0 && mbfx_simulation_advance(sim, row[0], NULL) != MBFX_STATUS_OK) break;
        if (!same_bits(mbfx_simulation_time(sim), row[0])) break;
        if (mbfx_simulation_outputs(sim, out, 3) != MBFX_STATUS_OK) break;
        /* The probes follow the POUTPUT ANGLE, which is the probe angle too. */
        if (!same_bits(out[1], row[1]) || !same_bits(out[2], row[2]) || !same_bits(out[0], row[1])) {
            printf("row %zu (t = %.17g): %.17g %.17g against %.17g %.17g\n", r, row[0], out[1],
                   out[2], row[1], row[2]);
            break;
        }
        ++matched;
    }
    CHECK(n_rows > 0 && matched == n_rows);
    fclose(rows);
    mbfx_simulation_free(sim);
}

/* Inputs, snapshots and reset. */
static void inputs_and_states(const char *text) {
    mbfx_error *err = NULL;
    mbfx_simulation *sim = pendulum(text, NULL), *fresh = pendulum(text, NULL);
    mbfx_simulation_state *state;
    double a[3], b[3], first[3];
    CHECK(sim != NULL && fresh != NULL);
    if (!sim || !fresh) return;
    CHECK(mbfx_simulation_set_input(sim, "torque", 0.3, &err) == MBFX_STATUS_OK && err == NULL);
    CHECK(mbfx_simulation_advance(sim, 0.5, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_time(sim) == 0.5);
    state = mbfx_simulation_state_save(sim);
    CHECK(state != NULL);
    CHECK(mbfx_simulation_advance(sim, 1.0, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(sim, first, 3) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_state_restore(sim, state) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_time(sim) == 0.5);
    CHECK(mbfx_simulation_advance(sim, 1.0, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(sim, a, 3) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_state_restore(sim, state) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_advance(sim, 1.0, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(sim, b, 3) == MBFX_STATUS_OK);
    CHECK(memcmp(a, b, sizeof a) == 0);
    /* Restarted at 0.5 s, the integrator takes other steps: the same motion within a
     * few ERRORs (1.2e-3 rad of 2.9 at ERROR 1e-3; 1.4e-6 at 1e-6), not the same bits. */
    CHECK(fabs(a[0] - first[0]) < 1e-2);
    mbfx_simulation_state_free(state);
    mbfx_simulation_state_free(NULL);
    /* Reset: the start, then the bits of a new simulation. */
    CHECK(mbfx_simulation_reset(sim) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_time(sim) == 0.0);
    CHECK(mbfx_simulation_advance(sim, 0.4, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_advance(fresh, 0.4, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(sim, a, 3) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(fresh, b, 3) == MBFX_STATUS_OK);
    CHECK(memcmp(a, b, sizeof a) == 0);
    /* A torque turns the pendulum the other way from where gravity swings it. */
    CHECK(mbfx_simulation_set_input(fresh, "VARIABLE/3", -50.0, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_advance(fresh, 0.6, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_advance(sim, 0.6, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(sim, a, 3) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_outputs(fresh, b, 3) == MBFX_STATUS_OK);
    CHECK(b[0] < a[0]);
    mbfx_simulation_free(sim);
    mbfx_simulation_free(fresh);
}

/* Every failure is a status with a message; NULLs are refused. */
static void errors(const char *text, const char *cart_pole) {
    mbfx_error *err = NULL;
    mbfx_simulation *sim;
    double out[3];
    const char *bad_probe[] = {"x=DX(999)"};
    CHECK(mbfx_simulation_new(NULL, NULL, 0.0, 0.0, NULL, 0, NULL, 0, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_new("oops\nPART/1, GROUND\nJOINT/1, REVOLUTE, I = 5\nEND\n", NULL, 0.0,
                              0.01, NULL, 0, NULL, 0, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_RUN_FAILED);
    CHECK(mbfx_error_code(err)[0] == 'E' && strlen(mbfx_error_message(err)) > 0);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_new(text, "rk4", 0.0, 0.01, NULL, 0, NULL, 0, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_INVALID_ARGUMENT);
    CHECK(strstr(mbfx_error_message(err), "rk4") != NULL);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_new(text, NULL, 0.0, 0.01, bad_probe, 1, NULL, 0, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_RUN_FAILED);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_advance(NULL, 1.0, &err) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_error_free(err);
    CHECK(isnan(mbfx_simulation_time(NULL)));
    CHECK(mbfx_simulation_output_count(NULL) == 0 && mbfx_simulation_output_name(NULL, 0) == NULL);
    CHECK(mbfx_simulation_outputs(NULL, out, 3) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_simulation_set_input(NULL, "TORQUE", 1.0, NULL) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_simulation_state_save(NULL) == NULL);
    CHECK(mbfx_simulation_state_restore(NULL, NULL) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_simulation_reset(NULL) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_simulation_free(NULL);

    sim = pendulum(text, NULL);
    CHECK(sim != NULL);
    if (!sim) return;
    CHECK(mbfx_simulation_state_restore(sim, NULL) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_simulation_outputs(sim, out, 2) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_simulation_outputs(sim, NULL, 3) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_simulation_set_input(sim, NULL, 1.0, NULL) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_simulation_set_input(sim, "thrust", 1.0, &err) == MBFX_STATUS_INVALID_ARGUMENT);
    CHECK(strstr(mbfx_error_message(err), "TORQUE") != NULL);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_set_input(sim, "ANGLE", 1.0, &err) == MBFX_STATUS_INVALID_ARGUMENT);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_set_input(sim, "TORQUE", NAN, NULL) == MBFX_STATUS_INVALID_ARGUMENT);
    CHECK(mbfx_simulation_advance(sim, 0.2, NULL) == MBFX_STATUS_OK);
    CHECK(mbfx_simulation_advance(sim, 0.1, &err) == MBFX_STATUS_INVALID_ARGUMENT);
    mbfx_error_free(err);
    CHECK(mbfx_simulation_advance(sim, NAN, NULL) == MBFX_STATUS_INVALID_ARGUMENT);
    CHECK(mbfx_simulation_advance(sim, 0.2, NULL) == MBFX_STATUS_OK);
    mbfx_simulation_free(sim);

    /* A failing integration: the status, the code, the time in the message. */
    sim = mbfx_simulation_new(cart_pole, NULL, 0.0, 0.1, NULL, 0, NULL, 0, NULL);
    CHECK(sim != NULL);
    if (!sim) return;
    {
        int k, status = MBFX_STATUS_OK;
        for (k = 1; k <= 10 && status == MBFX_STATUS_OK; ++k)
            status = mbfx_simulation_advance(sim, k * 0.1, &err);
        CHECK(status == MBFX_STATUS_RUN_FAILED);
        CHECK(err != NULL && strcmp(mbfx_error_code(err), "E0802") == 0);
        CHECK(err != NULL && strstr(mbfx_error_report(err), "0.451") != NULL);
        CHECK(mbfx_simulation_time(sim) > 0.45 && mbfx_simulation_time(sim) < 0.46);
        mbfx_error_free(err);
        /* Stopped: the next advance says so again. */
        CHECK(mbfx_simulation_advance(sim, 2.0, NULL) == MBFX_STATUS_RUN_FAILED);
        CHECK(mbfx_simulation_reset(sim) == MBFX_STATUS_OK);
        CHECK(mbfx_simulation_advance(sim, 0.1, NULL) == MBFX_STATUS_OK);
    }
    mbfx_simulation_free(sim);
}

int main(int argc, char **argv) {
    char *text, *cart_pole;
    if (argc != 4) {
        fprintf(stderr, "usage: simulation_test PENDULUM.adm ROWS.txt CART_POLE.adm\n");
        return 2;
    }
    text = slurp(argv[1]);
    cart_pole = slurp(argv[3]);
    if (!text || !cart_pole) {
        fprintf(stderr, "cannot read %s or %s\n", argv[1], argv[3]);
        return 2;
    }
    matches_run(text, argv[2]);
    inputs_and_states(text);
    errors(text, cart_pole);
    free(text);
    free(cart_pole);
    printf("%d checks, %d failed\n", checks, failures);
    return failures != 0;
}
