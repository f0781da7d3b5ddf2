/*
 * The C API from C: every function of include/mbfx.h, its values checked against closed
 * forms, both engines bit for bit, the array path against the single-point path, the
 * gradient, the entry pointer, and every error path. Built and run by capi/tests/c.rs;
 * prints "N passed, N failed" and exits non-zero when a check failed.
 */
#include "mbfx.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef MBFX_EXPECTED_VERSION
#error "build with -DMBFX_EXPECTED_VERSION=\"x.y.z\""
#endif

static int passed, failed;

static void check(int ok, const char *what, int line) {
    if (ok) {
        passed++;
    } else {
        failed++;
        fprintf(stderr, "api_test.c:%d: check failed: %s\n", line, what);
    }
}

#define CHECK(cond) check((cond) != 0, #cond, __LINE__)
#define N_OF(a) (sizeof(a) / sizeof((a)[0]))

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static int close_to(double got, double want) {
    return fabs(got - want) <= 1e-14 * fmax(1.0, fabs(want));
}

static int str_eq(const char *a, const char *b) { return a && b && strcmp(a, b) == 0; }

static int contains(const char *hay, const char *needle) {
    return hay && needle && strstr(hay, needle) != NULL;
}

static const int engines[2] = {MBFX_ENGINE_JIT, MBFX_ENGINE_INTERP};

/* STEP(x, 0, 0, 1, 1): the cubic x^2 (3 - 2x) between its ends. */
static double step01(double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    return x * x * (3.0 - 2.0 * x);
}

/* Compiles text over names, expecting success. */
static mbfx_expr *compile_ok(const char *text, const char *const *names, size_t n, int engine) {
    mbfx_error *err = (mbfx_error *)&err; /* must be overwritten with NULL */
    mbfx_expr *e = mbfx_compile(text, names, n, engine, &err);
    CHECK(e != NULL);
    CHECK(err == NULL);
    if (err) {
        fprintf(stderr, "%s", mbfx_error_report(err));
        mbfx_error_free(err);
    }
    return e;
}

/* Compiles text over names, expecting failure with status; returns the error. */
static mbfx_error *compile_fails(const char *text, const char *const *names, size_t n,
                                 int engine, mbfx_status status) {
    mbfx_error *err = NULL;
    mbfx_expr *e = mbfx_compile(text, names, n, engine, &err);
    CHECK(e == NULL);
    CHECK(err != NULL);
    CHECK(mbfx_error_status(err) == status);
    CHECK(mbfx_error_message(err) != NULL && strlen(mbfx_error_message(err)) > 0);
    CHECK(mbfx_error_report(err) != NULL && strlen(mbfx_error_report(err)) > 0);
    mbfx_expr_free(e);
    return err;
}

static void test_version_and_status_strings(void) {
    CHECK(str_eq(mbfx_version(), MBFX_EXPECTED_VERSION));
    const char *unknown = mbfx_status_string(-1);
    CHECK(str_eq(unknown, "unknown status"));
    CHECK(str_eq(mbfx_status_string(1000), "unknown status"));
    CHECK(str_eq(mbfx_status_string(MBFX_STATUS_OK), "ok"));
    for (int s = MBFX_STATUS_OK; s <= MBFX_STATUS_INTERNAL; s++) {
        CHECK(mbfx_status_string(s) != NULL && !str_eq(mbfx_status_string(s), unknown));
        for (int t = MBFX_STATUS_OK; t < s; t++)
            CHECK(!str_eq(mbfx_status_string(s), mbfx_status_string(t)));
    }
}

static void test_scalar_values_and_engines(void) {
    const char *text = "k*STEP(x, 0, 0, 1, 1) + SIN(TIME)";
    const char *names[] = {"x", "k"};
    mbfx_expr *e[2];
    for (int i = 0; i < 2; i++) {
        e[i] = compile_ok(text, names, 2, engines[i]);
        CHECK(mbfx_expr_n_variables(e[i]) == 2);
        CHECK(mbfx_expr_n_outputs(e[i]) == 1);
        CHECK(str_eq(mbfx_expr_text(e[i]), text));
        CHECK(str_eq(mbfx_expr_variable(e[i], 0), "x"));
        CHECK(str_eq(mbfx_expr_variable(e[i], 1), "k"));
        CHECK(mbfx_expr_variable(e[i], 2) == NULL);
        CHECK(str_eq(mbfx_expr_warnings(e[i]), ""));
    }
    const double xs[] = {-0.5, 0.0, 0.25, 0.5, 0.9, 1.0, 3.0};
    for (size_t p = 0; p < N_OF(xs); p++) {
        double vars[2] = {xs[p], 2.5}, t = 0.1 * (double)p;
        double out[2][1] = {{NAN}, {NAN}};
        for (int i = 0; i < 2; i++)
            CHECK(mbfx_expr_eval(e[i], vars, 2, t, out[i], 1) == MBFX_STATUS_OK);
        CHECK(close_to(out[0][0], 2.5 * step01(xs[p]) + sin(t)));
        CHECK(same_bits(out[0][0], out[1][0]));
    }
    /* The inputs may share the output buffer for one point. */
    double shared[2] = {0.5, 2.0};
    CHECK(mbfx_expr_eval(e[0], shared, 2, 0.0, shared, 1) == MBFX_STATUS_OK);
    CHECK(shared[0] == 2.0 * 0.5 * 0.5 * (3.0 - 2.0 * 0.5));
    mbfx_expr_free(e[0]);
    mbfx_expr_free(e[1]);

    /* No variables: names may be NULL. */
    mbfx_expr *c = compile_ok("2*PI + TIME", NULL, 0, MBFX_ENGINE_JIT);
    double v = NAN;
    CHECK(mbfx_expr_n_variables(c) == 0);
    CHECK(mbfx_expr_eval(c, NULL, 0, 1.0, &v, 1) == MBFX_STATUS_OK);
    CHECK(close_to(v, 2.0 * acos(-1.0) + 1.0));
    mbfx_expr_free(c);
}

static void test_arrays_match_single_points(void) {
    const char *names[] = {"x", "k"};
    for (int i = 0; i < 2; i++) {
        mbfx_expr *e = compile_ok("k*STEP(x, 0, 0, 1, 1) + TIME**2", names, 2, engines[i]);
        enum { N = 6 };
        double x[N] = {-1.0, 0.1, 0.3, 0.5, 0.75, 2.0};
        double k = 3.0, times[N] = {0.0, 0.5, 1.0, 1.5, 2.0, 2.5};
        const double *columns[2] = {x, &k};
        size_t strides[2] = {1, 0};
        double out[N];
        CHECK(mbfx_expr_eval_n(e, N, columns, strides, 2, times, 0.0, out, N) == MBFX_STATUS_OK);
        for (int p = 0; p < N; p++) {
            double one, vars[2] = {x[p], k};
            CHECK(mbfx_expr_eval(e, vars, 2, times[p], &one, 1) == MBFX_STATUS_OK);
            CHECK(same_bits(out[p], one));
            CHECK(close_to(out[p], k * step01(x[p]) + times[p] * times[p]));
        }
        /* A row-major table (stride 2) and a scalar TIME. */
        double table[2 * N];
        for (int p = 0; p < N; p++) {
            table[2 * p] = x[p];
            table[2 * p + 1] = 1.0 + p;
        }
        const double *rows[2] = {table, table + 1};
        size_t twos[2] = {2, 2};
        CHECK(mbfx_expr_eval_n(e, N, rows, twos, 2, NULL, 0.5, out, N) == MBFX_STATUS_OK);
        for (int p = 0; p < N; p++) {
            double one;
            CHECK(mbfx_expr_eval(e, &table[2 * p], 2, 0.5, &one, 1) == MBFX_STATUS_OK);
            CHECK(same_bits(out[p], one));
        }
        /* strides NULL: every column contiguous. */
        double ks[N] = {1, 2, 3, 4, 5, 6};
        const double *both[2] = {x, ks};
        CHECK(mbfx_expr_eval_n(e, N, both, NULL, 2, times, 0.0, out, N) == MBFX_STATUS_OK);
        for (int p = 0; p < N; p++)
            CHECK(close_to(out[p], ks[p] * step01(x[p]) + times[p] * times[p]));
        /* Every column constant and no TIME array: n copies of one point. */
        double one_x = 0.5;
        const double *consts[2] = {&one_x, &k};
        size_t zeros[2] = {0, 0};
        CHECK(mbfx_expr_eval_n(e, 3, consts, zeros, 2, NULL, 1.0, out, 3) == MBFX_STATUS_OK);
        CHECK(out[0] == 3.0 * 0.5 + 1.0 && same_bits(out[1], out[0]) && same_bits(out[2], out[0]));
        /* No points: nothing to write, out may be NULL. */
        CHECK(mbfx_expr_eval_n(e, 0, both, NULL, 2, NULL, 0.0, NULL, 0) == MBFX_STATUS_OK);
        mbfx_expr_free(e);
    }
    /* Many contiguous points (the JIT engine's block evaluator, 128 points at a time and a
       partial last block), with IF arms picked differently point to point: the same bits
       as one point at a time, in both engines. */
    for (int i = 0; i < 2; i++) {
        mbfx_expr *e = compile_ok("IF(x - 0.5: SIN(x)*k, k, IMPACT(x, k, 1, 1E5, 1.5, 50, 0.1)) + TIME",
                                  names, 2, engines[i]);
        enum { M = 300 };
        static double xs[M], ks[M], ts[M], many[M];
        for (int p = 0; p < M; p++) {
            xs[p] = (p % 7 == 3) ? 0.5 : 1.5 * sin(0.37 * p) + 0.6;
            ks[p] = cos(0.11 * p);
            ts[p] = 0.01 * p;
        }
        const double *cols2[2] = {xs, ks};
        CHECK(mbfx_expr_eval_n(e, M, cols2, NULL, 2, ts, 0.0, many, M) == MBFX_STATUS_OK);
        int same = 1;
        for (int p = 0; p < M; p++) {
            double one, vars[2] = {xs[p], ks[p]};
            CHECK(mbfx_expr_eval(e, vars, 2, ts[p], &one, 1) == MBFX_STATUS_OK);
            same &= same_bits(many[p], one);
        }
        CHECK(same);
        mbfx_expr_free(e);
    }
    /* A vector: three outputs per point, point after point. */
    const char *x_only[] = {"x"};
    mbfx_expr *v = compile_ok("[x, x*x, TIME]", x_only, 1, MBFX_ENGINE_JIT);
    CHECK(mbfx_expr_n_outputs(v) == 3);
    double xs[2] = {3.0, -2.0}, ts[2] = {0.25, 0.5}, out[6];
    const double *cols[1] = {xs};
    CHECK(mbfx_expr_eval_n(v, 2, cols, NULL, 1, ts, 0.0, out, 6) == MBFX_STATUS_OK);
    CHECK(out[0] == 3.0 && out[1] == 9.0 && out[2] == 0.25);
    CHECK(out[3] == -2.0 && out[4] == 4.0 && out[5] == 0.5);
    mbfx_expr_free(v);
}

static void test_gradient(void) {
    const char *names[] = {"x"};
    const char *wrt[] = {"X", "time"};
    double got[2][3];
    for (int i = 0; i < 2; i++) {
        mbfx_expr *e = compile_ok("x**3*SIN(TIME)", names, 1, engines[i]);
        mbfx_error *err = (mbfx_error *)&err;
        mbfx_expr *g = mbfx_expr_gradient(e, wrt, 2, &err);
        CHECK(g != NULL && err == NULL);
        /* With no names (and no error pointer): the outputs alone. */
        mbfx_expr *g0 = mbfx_expr_gradient(e, NULL, 0, NULL);
        CHECK(g0 != NULL && mbfx_expr_n_outputs(g0) == 1);
        mbfx_expr_free(g0);
        /* The gradient is independent of the expression it was taken of. */
        mbfx_expr_free(e);
        CHECK(mbfx_expr_n_outputs(g) == 3);
        CHECK(mbfx_expr_n_variables(g) == 1);
        CHECK(str_eq(mbfx_expr_text(g), "x**3*SIN(TIME)"));
        double x = 2.0, t = 0.5;
        CHECK(mbfx_expr_eval(g, &x, 1, t, got[i], 3) == MBFX_STATUS_OK);
        CHECK(close_to(got[i][0], x * x * x * sin(t)));
        CHECK(close_to(got[i][1], 3.0 * x * x * sin(t)));
        CHECK(close_to(got[i][2], x * x * x * cos(t)));
        mbfx_expr_free(g);
    }
    for (int j = 0; j < 3; j++) CHECK(same_bits(got[0][j], got[1][j]));
}

static void test_entry(void) {
    const char *names[] = {"x", "k"};
    mbfx_expr *e = compile_ok("k*STEP(x, 0, 0, 1, 1) + SIN(TIME)", names, 2, MBFX_ENGINE_JIT);
    mbfx_entry_fn f = NULL;
    CHECK(mbfx_expr_entry(e, &f) == MBFX_STATUS_OK);
    CHECK(f != NULL);
    if (f) {
        double args[3] = {0.5, 2.0, 0.75}, want = NAN;
        CHECK(mbfx_expr_eval(e, args, 2, 0.75, &want, 1) == MBFX_STATUS_OK);
        CHECK(same_bits(f(3, args, NULL), want));
        /* Without TIME in x, TIME is 0. */
        CHECK(mbfx_expr_eval(e, args, 2, 0.0, &want, 1) == MBFX_STATUS_OK);
        CHECK(same_bits(f(2, args, NULL), want));
        CHECK(close_to(f(2, args, NULL), 2.0 * step01(0.5)));
        /* Too few values: NaN, nothing read. */
        CHECK(isnan(f(1, args, NULL)));
        CHECK(isnan(f(-1, args, NULL)));
    }
    /* A gradient's entry writes its outputs through out. */
    const char *wrt[] = {"x"};
    mbfx_expr *g = mbfx_expr_gradient(e, wrt, 1, NULL);
    mbfx_entry_fn gf = NULL;
    CHECK(g != NULL && mbfx_expr_entry(g, &gf) == MBFX_STATUS_OK && gf != NULL);
    if (gf) {
        double args[3] = {0.5, 2.0, 0.0}, out[2] = {NAN, NAN}, want[2];
        CHECK(isnan(gf(3, args, NULL)));
        double first = gf(3, args, out);
        CHECK(mbfx_expr_eval(g, args, 2, 0.0, want, 2) == MBFX_STATUS_OK);
        CHECK(same_bits(first, want[0]) && same_bits(out[0], want[0]));
        CHECK(same_bits(out[1], want[1]));
        CHECK(close_to(out[1], 2.0 * 6.0 * 0.5 * (1.0 - 0.5))); /* k * 6x(1 - x) */
    }
    mbfx_expr_free(g);
    /* The interpreter has no entry. */
    mbfx_expr *interp = compile_ok("x + k", names, 2, MBFX_ENGINE_INTERP);
    f = (mbfx_entry_fn)1;
    CHECK(mbfx_expr_entry(interp, &f) == MBFX_STATUS_NO_ENTRY);
    CHECK(f == NULL);
    mbfx_expr_free(interp);
    f = (mbfx_entry_fn)1;
    CHECK(mbfx_expr_entry(NULL, &f) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(f == NULL);
    CHECK(mbfx_expr_entry(e, NULL) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_expr_free(e);
}

static void test_compile_errors(void) {
    const char *x[] = {"x"};
    /* A syntax error: its code, its place, and a caret under it. */
    mbfx_error *err = compile_fails("x + * 2", x, 1, MBFX_ENGINE_JIT, MBFX_STATUS_COMPILE_ERROR);
    CHECK(str_eq(mbfx_error_code(err), "E0201"));
    size_t line = 0, column = 0;
    CHECK(mbfx_error_position(err, &line, &column));
    CHECK(line == 1 && column == 5);
    const char *report = mbfx_error_report(err);
    CHECK(contains(report, "[E0201] Error:"));
    CHECK(contains(report, "expression:1:5"));
    CHECK(contains(report, "x + * 2"));
    CHECK(contains(report, "\n   |     `-- here"));
    CHECK(contains(report, mbfx_error_message(err)));
    mbfx_error_free(err);
    /* On a continuation line (a comma in column one). */
    err = compile_fails("x +\n,   * 2", x, 1, MBFX_ENGINE_INTERP, MBFX_STATUS_COMPILE_ERROR);
    CHECK(str_eq(mbfx_error_code(err), "E0201"));
    CHECK(mbfx_error_position(err, &line, NULL) && line == 2);
    CHECK(mbfx_error_position(err, NULL, &column) && column == 5);
    CHECK(contains(mbfx_error_report(err), "expression:2:5"));
    mbfx_error_free(err);
    /* A line break without the comma: the first error is on line 1. */
    err = compile_fails("x +\n  * 2", x, 1, MBFX_ENGINE_INTERP, MBFX_STATUS_COMPILE_ERROR);
    CHECK(str_eq(mbfx_error_code(err), "E0101"));
    CHECK(mbfx_error_position(err, &line, &column) && line == 1 && column == 4);
    CHECK(contains(mbfx_error_report(err), "expression:2:3")); /* and the `*` after it */
    mbfx_error_free(err);
    err = compile_fails("x + ", x, 1, MBFX_ENGINE_JIT, MBFX_STATUS_COMPILE_ERROR);
    CHECK(str_eq(mbfx_error_code(err), "E0202"));
    mbfx_error_free(err);
    /* A name that is not a variable of the expression. */
    err = compile_fails("x + y", x, 1, MBFX_ENGINE_JIT, MBFX_STATUS_COMPILE_ERROR);
    CHECK(str_eq(mbfx_error_code(err), "E0302"));
    CHECK(mbfx_error_position(err, &line, &column) && line == 1 && column == 5);
    mbfx_error_free(err);
    /* A measure needs a model. */
    err = compile_fails("DX(1, 2)", NULL, 0, MBFX_ENGINE_JIT, MBFX_STATUS_COMPILE_ERROR);
    CHECK(str_eq(mbfx_error_code(err), "E0308"));
    mbfx_error_free(err);
    /* No error pointer: the failure is still NULL. */
    CHECK(mbfx_compile("x +", x, 1, MBFX_ENGINE_JIT, NULL) == NULL);
}

static void test_bad_variables(void) {
    const char *builtin[] = {"PI"}, *number[] = {"1x"}, *twice[] = {"x", "X"}, *empty[] = {""};
    const char *const *lists[] = {builtin, number, twice, empty};
    size_t counts[] = {1, 1, 2, 1};
    for (size_t i = 0; i < N_OF(lists); i++) {
        mbfx_error *err =
            compile_fails("1", lists[i], counts[i], MBFX_ENGINE_JIT, MBFX_STATUS_BAD_VARIABLE);
        CHECK(str_eq(mbfx_error_code(err), "E0503"));
        CHECK(contains(mbfx_error_report(err), "[E0503] Error: variable"));
        CHECK(!mbfx_error_position(err, NULL, NULL));
        mbfx_error_free(err);
    }
    /* A gradient in a name that is no variable. */
    const char *names[] = {"x"};
    mbfx_expr *e = compile_ok("x*x", names, 1, MBFX_ENGINE_JIT);
    const char *z[] = {"z"};
    mbfx_error *err = NULL;
    CHECK(mbfx_expr_gradient(e, z, 1, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_BAD_VARIABLE);
    CHECK(contains(mbfx_error_message(err), "`z`"));
    mbfx_error_free(err);
    const char *null_name[] = {NULL};
    CHECK(mbfx_expr_gradient(e, null_name, 1, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_error_free(err);
    CHECK(mbfx_expr_gradient(e, NULL, 1, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_error_free(err);
    CHECK(mbfx_expr_gradient(NULL, names, 1, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_NULL_ARGUMENT);
    mbfx_error_free(err);
    const char *bad_utf8[] = {"x\xff"};
    CHECK(mbfx_expr_gradient(e, bad_utf8, 1, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_INVALID_UTF8);
    mbfx_error_free(err);
    mbfx_expr_free(e);
}

static void test_not_differentiable(void) {
    /* A library function's partials come from its companion, which has no derivative of
       its own: the second gradient of SWEEP is refused. */
    const char *names[] = {"x", "y"}, *wx[] = {"x"}, *wy[] = {"y"};
    mbfx_expr *e = compile_ok("SWEEP(x, 1, 0, y, 5, 10, 0.5)", names, 2, MBFX_ENGINE_JIT);
    mbfx_expr *g = mbfx_expr_gradient(e, wx, 1, NULL);
    CHECK(g != NULL);
    mbfx_error *err = NULL;
    CHECK(mbfx_expr_gradient(g, wy, 1, &err) == NULL);
    CHECK(mbfx_error_status(err) == MBFX_STATUS_NOT_DIFFERENTIABLE);
    CHECK(contains(mbfx_error_message(err), "SWEEP"));
    mbfx_error_free(err);
    mbfx_expr_free(g);
    mbfx_expr_free(e);
}

static void test_argument_errors(void) {
    const char *x[] = {"x"};
    mbfx_error *err;
    /* NULL text, NULL names, a NULL name. */
    err = compile_fails(NULL, x, 1, MBFX_ENGINE_JIT, MBFX_STATUS_NULL_ARGUMENT);
    CHECK(str_eq(mbfx_error_code(err), ""));
    CHECK(contains(mbfx_error_message(err), "text"));
    CHECK(!mbfx_error_position(err, NULL, NULL));
    mbfx_error_free(err);
    err = compile_fails("x", NULL, 1, MBFX_ENGINE_JIT, MBFX_STATUS_NULL_ARGUMENT);
    mbfx_error_free(err);
    const char *second_null[] = {"x", NULL};
    err = compile_fails("x", second_null, 2, MBFX_ENGINE_JIT, MBFX_STATUS_NULL_ARGUMENT);
    CHECK(contains(mbfx_error_message(err), "names[1]"));
    mbfx_error_free(err);
    /* Invalid UTF-8 in the text and in a name. */
    err = compile_fails("x + \xc3\x28", x, 1, MBFX_ENGINE_JIT, MBFX_STATUS_INVALID_UTF8);
    CHECK(contains(mbfx_error_message(err), "byte 4"));
    mbfx_error_free(err);
    const char *bad_name[] = {"\xff"};
    err = compile_fails("1", bad_name, 1, MBFX_ENGINE_JIT, MBFX_STATUS_INVALID_UTF8);
    CHECK(contains(mbfx_error_message(err), "names[0]"));
    mbfx_error_free(err);
    /* An engine that does not exist. */
    err = compile_fails("x", x, 1, 7, MBFX_STATUS_INVALID_ARGUMENT);
    mbfx_error_free(err);
    err = compile_fails("x", x, 1, -1, MBFX_STATUS_INVALID_ARGUMENT);
    mbfx_error_free(err);

    /* One point: wrong lengths and NULLs leave out alone. */
    const char *names[] = {"x", "y"};
    mbfx_expr *e = compile_ok("x*y", names, 2, MBFX_ENGINE_JIT);
    double vars[2] = {2.0, 3.0}, out[2] = {-1.0, -1.0};
    CHECK(mbfx_expr_eval(NULL, vars, 2, 0.0, out, 1) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval(e, NULL, 2, 0.0, out, 1) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval(e, vars, 2, 0.0, NULL, 1) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval(e, vars, 1, 0.0, out, 1) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_expr_eval(e, vars, 3, 0.0, out, 1) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_expr_eval(e, vars, 2, 0.0, out, 2) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_expr_eval(e, vars, 2, 0.0, out, 0) == MBFX_STATUS_BAD_LENGTH);
    CHECK(out[0] == -1.0 && out[1] == -1.0);
    /* A misaligned array. */
    unsigned char raw[4 * sizeof(double)];
    memset(raw, 0, sizeof raw);
    const double *odd = (const double *)(void *)(raw + 1);
    CHECK(mbfx_expr_eval(e, odd, 2, 0.0, out, 1) == MBFX_STATUS_INVALID_ARGUMENT);

    /* Many points. */
    double xs[3] = {1, 2, 3}, ys[3] = {4, 5, 6}, many[3] = {-1, -1, -1};
    const double *cols[2] = {xs, ys}, *one_null[2] = {xs, NULL}, *cols_odd[2] = {xs, odd};
    size_t strides[2] = {1, 1}, huge[2] = {1, SIZE_MAX / 2};
    CHECK(mbfx_expr_eval_n(NULL, 3, cols, NULL, 2, NULL, 0, many, 3) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval_n(e, 3, NULL, NULL, 2, NULL, 0, many, 3) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval_n(e, 3, one_null, NULL, 2, NULL, 0, many, 3) ==
          MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval_n(e, 3, cols, NULL, 2, NULL, 0, NULL, 3) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_expr_eval_n(e, 3, cols, NULL, 1, NULL, 0, many, 3) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_expr_eval_n(e, 3, cols, NULL, 2, NULL, 0, many, 2) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_expr_eval_n(e, 3, cols, huge, 2, NULL, 0, many, 3) == MBFX_STATUS_BAD_LENGTH);
    CHECK(mbfx_expr_eval_n(e, 3, cols_odd, strides, 2, NULL, 0, many, 3) ==
          MBFX_STATUS_INVALID_ARGUMENT);
    CHECK(many[0] == -1 && many[1] == -1 && many[2] == -1);
    CHECK(mbfx_expr_eval_n(e, 3, cols, strides, 2, NULL, 0, many, 3) == MBFX_STATUS_OK);
    CHECK(many[0] == 4 && many[1] == 10 && many[2] == 18);
    mbfx_expr_free(e);
    /* n times the outputs overflows size_t. */
    const char *one[] = {"x"};
    mbfx_expr *v = compile_ok("[x, x, x]", one, 1, MBFX_ENGINE_INTERP);
    const double *vcols[1] = {xs};
    size_t zero[1] = {0};
    CHECK(mbfx_expr_eval_n(v, SIZE_MAX / 2, vcols, zero, 1, NULL, 0, many, 3) ==
          MBFX_STATUS_BAD_LENGTH);
    mbfx_expr_free(v);

    /* Accessors and frees take NULL. */
    CHECK(mbfx_expr_n_variables(NULL) == 0);
    CHECK(mbfx_expr_n_outputs(NULL) == 0);
    CHECK(mbfx_expr_text(NULL) == NULL);
    CHECK(mbfx_expr_variable(NULL, 0) == NULL);
    CHECK(mbfx_expr_warnings(NULL) == NULL);
    CHECK(mbfx_error_status(NULL) == MBFX_STATUS_NULL_ARGUMENT);
    CHECK(mbfx_error_code(NULL) == NULL);
    CHECK(mbfx_error_message(NULL) == NULL);
    CHECK(mbfx_error_report(NULL) == NULL);
    size_t sink = 7;
    CHECK(!mbfx_error_position(NULL, &sink, NULL) && sink == 7);
    mbfx_expr_free(NULL);
    mbfx_error_free(NULL);
}

/* Several threads evaluate one expression at once, and each compiles its own (every
   thread has its own JIT): the same bits as on the main thread. */
struct shared_eval {
    const mbfx_expr *expr;
    double want;
    int mismatches;
};

static void *evaluate_many(void *arg) {
    struct shared_eval *s = arg;
    const char *names[] = {"x", "k"};
    mbfx_expr *own = mbfx_compile("k*STEP(x, 0, 0, 1, 1) + SIN(TIME)", names, 2,
                                  MBFX_ENGINE_JIT, NULL);
    mbfx_entry_fn f = NULL;
    if (own == NULL || mbfx_expr_entry(own, &f) != MBFX_STATUS_OK) s->mismatches++;
    for (int i = 0; i < 2000; i++) {
        double vars[2] = {0.3, 1.5}, out = NAN, args[3] = {0.3, 1.5, 0.7};
        if (mbfx_expr_eval(s->expr, vars, 2, 0.7, &out, 1) != MBFX_STATUS_OK ||
            !same_bits(out, s->want))
            s->mismatches++;
        if (f && !same_bits(f(3, args, NULL), s->want)) s->mismatches++;
    }
    mbfx_expr_free(own);
    return NULL;
}

static void test_threads(void) {
    const char *names[] = {"x", "k"};
    for (int i = 0; i < 2; i++) {
        mbfx_expr *e = compile_ok("k*STEP(x, 0, 0, 1, 1) + SIN(TIME)", names, 2, engines[i]);
        double vars[2] = {0.3, 1.5};
        struct shared_eval s[4];
        pthread_t ids[4];
        for (int t = 0; t < 4; t++) {
            s[t].expr = e;
            s[t].mismatches = 0;
            CHECK(mbfx_expr_eval(e, vars, 2, 0.7, &s[t].want, 1) == MBFX_STATUS_OK);
            CHECK(pthread_create(&ids[t], NULL, evaluate_many, &s[t]) == 0);
        }
        for (int t = 0; t < 4; t++) {
            CHECK(pthread_join(ids[t], NULL) == 0);
            CHECK(s[t].mismatches == 0);
        }
        mbfx_expr_free(e);
    }
}

int main(void) {
    test_version_and_status_strings();
    test_scalar_values_and_engines();
    test_arrays_match_single_points();
    test_gradient();
    test_entry();
    test_compile_errors();
    test_bad_variables();
    test_not_differentiable();
    test_argument_errors();
    test_threads();
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
