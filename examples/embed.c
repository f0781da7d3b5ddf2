/*
 * A spring-mass system m x'' = F(x, v, TIME) integrated by a plain C loop (classical
 * Runge-Kutta, 4th order), its force an mbfx expression compiled over the variables
 * x and v and called through its raw entry pointer at every stage. The final state is
 * printed against the closed form of the free oscillator, undamped and damped; the
 * program exits with 1 when they differ by more than 1e-9.
 *
 * Build and run from the repository root:
 *
 *   cargo build --release -p mbfx-capi
 *   cc -std=c99 -O2 -Iinclude examples/embed.c -Ltarget/release -lmbfx_c -Wl,-rpath,"$PWD/target/release" -lm -o embed
 *   ./embed
 *
 * or link the static library instead (no run-time path needed):
 *
 *   cc -std=c99 -O2 -Iinclude examples/embed.c target/release/libmbfx_c.a \
 *      -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc -o embed
 */
#include "mbfx.h"

#include <math.h>
#include <stdio.h>

/* m x'' = -k x - c v with x(0) = X0, v(0) = V0. */
static const double MASS = 2.0, STIFFNESS = 8.0, X0 = 1.0, V0 = 0.0;
static const double END = 10.0, DT = 1e-3;

/* The closed form of the free oscillator with damping c (underdamped or undamped):
   x = e^(-s t) (x0 cos(wd t) + (v0 + s x0) / wd sin(wd t)), s = c / 2m, wd^2 = k/m - s^2. */
static void closed_form(double c, double t, double *x, double *v) {
    double s = c / (2.0 * MASS), w0sq = STIFFNESS / MASS, wd = sqrt(w0sq - s * s);
    double e = exp(-s * t), cs = cos(wd * t), sn = sin(wd * t);
    *x = e * (X0 * cs + (V0 + s * X0) / wd * sn);
    *v = e * (V0 * cs - (w0sq * X0 + s * V0) / wd * sn);
}

/* The acceleration at (x, v, t): the entry takes the variables in order, then TIME. */
static double accel(mbfx_entry_fn force, double x, double v, double t) {
    double args[3] = {x, v, t};
    return force(3, args, NULL) / MASS;
}

/* Integrates from (X0, V0) to END; returns 0, or 1 when the expression fails. */
static int simulate(const char *text, double damping, const char *label) {
    const char *names[] = {"x", "v"};
    mbfx_error *error = NULL;
    mbfx_expr *expr = mbfx_compile(text, names, 2, MBFX_ENGINE_JIT, &error);
    if (expr == NULL) {
        fprintf(stderr, "%s", mbfx_error_report(error));
        mbfx_error_free(error);
        return 1;
    }
    mbfx_entry_fn force = NULL;
    if (mbfx_expr_entry(expr, &force) != MBFX_STATUS_OK) {
        mbfx_expr_free(expr);
        return 1;
    }
    double x = X0, v = V0, t = 0.0;
    long steps = lround(END / DT);
    for (long i = 0; i < steps; i++) {
        double h = DT;
        double k1x = v, k1v = accel(force, x, v, t);
        double k2x = v + h / 2 * k1v, k2v = accel(force, x + h / 2 * k1x, k2x, t + h / 2);
        double k3x = v + h / 2 * k2v, k3v = accel(force, x + h / 2 * k2x, k3x, t + h / 2);
        double k4x = v + h * k3v, k4v = accel(force, x + h * k3x, k4x, t + h);
        x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
        v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
        t = (double)(i + 1) * h;
    }
    /* The entry dies with its expression: free it after the last call. */
    mbfx_expr_free(expr);
    double xe, ve;
    closed_form(damping, t, &xe, &ve);
    double err = fmax(fabs(x - xe), fabs(v - ve));
    printf("%-8s F = %-14s x(%g) = %+.12f (closed form %+.12f)  v = %+.12f (%+.12f)  error %.1e\n",
           label, text, t, x, xe, v, ve, err);
    return err <= 1e-9 ? 0 : 1;
}

int main(void) {
    int failed = 0;
    failed |= simulate("-8*x", 0.0, "undamped");
    failed |= simulate("-8*x - 0.8*v", 0.8, "damped");
    return failed;
}
