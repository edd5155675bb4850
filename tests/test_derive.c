/* test_derive.c — the --derive expression grammar (vsv_expr_*): precedence,
 * the associativity of ^, unary minus, functions, NaN in and out, and every
 * error message with the character it names. */
#include "vsv_convert.h"
#include "vsv_testlib.h"

#include <math.h>
#include <string.h>

static const char *const NAMES[] = {"a", "b", "RAD TEND", "PM2.5"};
enum { N = 4 };
static const float A[N] = {2, -3, 0.5f, NAN}, B[N] = {3, 4, 0, 1}, C[N] = {10, 10, 10, 10}, D[N] = {1, 1, 1, 1};

/* text at every cell; NaN where want is NaN. */
static void value(const char *text, const float want[N])
{
    vsv_expr *e = NULL;
    char msg[200];
    int pos;
    const int rc = vsv_expr_compile(text, NAMES, 4, &e, msg, sizeof msg, &pos);
    char name[160];
    snprintf(name, sizeof name, "%s", text);
    if (!CHECK(rc == 0, name, "compile: %s at %d", msg, pos))
        return;
    float out[N];
    const float *in[4] = {A, B, C, D};
    vsv_expr_eval(e, in, N, out);
    int ok = 1;
    for (int c = 0; c < N; c++)
        ok &= isnan(want[c]) ? isnan(out[c]) : fabsf(out[c] - want[c]) <= 1e-6f * fmaxf(1, fabsf(want[c]));
    CHECK(ok, name, "got %g %g %g %g, wanted %g %g %g %g", out[0], out[1], out[2], out[3], want[0], want[1], want[2],
          want[3]);
    vsv_expr_free(e);
}

/* text fails with msg at character pos. */
static void error(const char *text, const char *want, int want_pos)
{
    vsv_expr *e = NULL;
    char msg[200];
    int pos;
    const int rc = vsv_expr_compile(text, NAMES, 4, &e, msg, sizeof msg, &pos);
    char name[200];
    snprintf(name, sizeof name, "'%.60s' fails: %s at %d", text, want, want_pos);
    CHECK(rc == VSV_EINVAL && !e && strstr(msg, want) && pos == want_pos, name, "rc %d, '%s' at %d", rc, msg, pos);
    vsv_expr_free(e);
}

/* Random strings over the grammar's alphabet: each compiles, or fails with a
 * message and a position inside the text (or just past it); what compiles
 * evaluates (under SAN=1: no read or write outside the stack). */
static void random_texts(void)
{
    static const char alphabet[] = "ab()+-*/^,.0123456789e \"sqrtminaxlogbs";
    uint64_t seed = 35;
    int compiled = 0, bad = 0;
    for (int k = 0; k < 20000; k++) {
        char text[48];
        const int len = (int)(vsv_test_rand(&seed) % (sizeof text - 1));
        for (int i = 0; i < len; i++)
            text[i] = alphabet[vsv_test_rand(&seed) % (sizeof alphabet - 1)];
        text[len] = 0;
        vsv_expr *e = NULL;
        char msg[200] = "";
        int pos = -1;
        const int rc = vsv_expr_compile(text, NAMES, 4, &e, msg, sizeof msg, &pos);
        if (rc == 0 && e) {
            float out[N];
            const float *in[4] = {A, B, C, D};
            vsv_expr_eval(e, in, N, out);
            compiled++;
        } else if (rc != VSV_EINVAL || e || !msg[0] || pos < 1 || pos > len + 1) {
            bad++;
        }
        vsv_expr_free(e);
    }
    CHECK(!bad && compiled > 100, "20000 random texts: each compiles or says what and where", "%d bad, %d compiled",
          bad, compiled);
}

int main(void)
{
    const float nan = NAN;
    /* precedence: * / over + -, ^ over * and over unary minus */
    value("1+2*3", (float[]){7, 7, 7, 7});
    value("(1+2)*3", (float[]){9, 9, 9, 9});
    value("a-b-1", (float[]){-2, -8, -0.5f, nan});
    value("12/2/3", (float[]){2, 2, 2, 2});
    value("2^3^2", (float[]){512, 512, 512, 512});
    value("(2^3)^2", (float[]){64, 64, 64, 64});
    value("-2^2", (float[]){-4, -4, -4, -4});
    value("2^-1", (float[]){0.5f, 0.5f, 0.5f, 0.5f});
    value("--a", (float[]){2, -3, 0.5f, nan});
    value("-a*b", (float[]){-6, 12, 0, nan});
    value("+a", (float[]){2, -3, 0.5f, nan});
    value("a*b+1", (float[]){7, -11, 1, nan});
    value("1.5e1 + .5 + 2E-1", (float[]){15.7f, 15.7f, 15.7f, 15.7f});
    /* functions */
    value("sqrt(b)", (float[]){sqrtf(3), 2, 0, 1});
    value("exp(1)", (float[]){expf(1), expf(1), expf(1), expf(1)});
    value("log(\"RAD TEND\")", (float[]){logf(10), logf(10), logf(10), logf(10)});
    value("abs(a)", (float[]){2, 3, 0.5f, nan});
    value("min(a, b)", (float[]){2, -3, 0, nan});
    value("max(a, b, PM2.5)", (float[]){3, 4, 1, nan});
    value("min(b, 1, 0.5)", (float[]){0.5f, 0.5f, 0, 0.5f});
    /* NaN in, NaN out: also where C's pow and fmin give a number */
    value("a^0", (float[]){1, 1, 1, nan});
    value("1^a", (float[]){1, 1, 1, nan});
    value("max(a, 5)", (float[]){5, 5, 5, nan});
    value("a*0", (float[]){0, 0, 0, nan});
    /* what is not a finite float is NaN: division by zero, log 0, sqrt of a
     * negative, overflow */
    value("1/b", (float[]){1.0f / 3, 0.25f, nan, 1});
    value("0/b", (float[]){0, 0, nan, 0});
    value("log(b)", (float[]){logf(3), logf(4), nan, 0});
    value("sqrt(a)", (float[]){sqrtf(2), nan, sqrtf(0.5f), nan});
    value("1e30*1e30", (float[]){nan, nan, nan, nan});
    /* uses */
    vsv_expr *e = NULL;
    char msg[200];
    int pos;
    if (!vsv_expr_compile("b + \"RAD TEND\"", NAMES, 4, &e, msg, sizeof msg, &pos)) {
        CHECK(!vsv_expr_uses(e, 0) && vsv_expr_uses(e, 1) && vsv_expr_uses(e, 2) && !vsv_expr_uses(e, 3) &&
                  !vsv_expr_uses(e, 4) && !vsv_expr_uses(e, -1),
              "uses: the inputs read, and no others");
        vsv_expr_free(e);
    }
    /* every error, at its character (1-based) */
    error("", "expected a value", 1);
    error("a+*2", "expected a value", 3);
    error("a+", "expected a value", 3);
    error("a**2", "expected a value", 3);
    error("c*2", "unknown name 'c'", 1);
    error("a + RAD", "unknown name 'RAD'", 5);
    error("foo(a)", "unknown function 'foo' (there are sqrt exp log abs min max)", 1);
    error("(a+b", "expected ')'", 5);
    error("min(a b)", "expected ',' or ')'", 7);
    error("1 + sqrt(a, b)", "sqrt takes one argument, not 2", 5);
    error("max(a)", "max takes two or more arguments, not 1", 1);
    error("a b", "expected an operator or the end, not 'b'", 3);
    error("a)", "expected an operator or the end, not ')'", 2);
    error("a $ b", "expected an operator or the end, not '$'", 3);
    error("$", "expected a value", 1);
    error("2*\"RAD TEND", "unterminated quoted name", 3);
    error("1 + .", "malformed number", 5);
    error("1e+x", "malformed exponent", 2);
    error("1e999", "number out of range", 1);
    char deep[200] = "", lng[1200] = "a", name[120];
    for (int i = 0; i < 40; i++)
        strcat(deep, "(");
    strcat(deep, "a");
    error(deep, "too deeply nested", 33); /* the 33rd ( */
    for (int i = 0; i < 300; i++)
        strcat(lng, "+a");
    error(lng, "too long (more than 256 operations)", 258); /* where the 257th operation ends */
    memset(name, 'x', 100);
    name[100] = 0;
    error(name, "name too long", 1);
    random_texts();
    return vsv_test_done();
}
