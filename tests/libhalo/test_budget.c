/* halo_budget_choose: the cheapest row within the error bound, and its edge cases
 * (no row fits, NaN and infinite rows, ties, a bound of 0, invalid arguments). */
#include "check.h"

static int test_cheapest_within(void)
{
    const halo_budget_row rows[] = {{2.0, 0.0}, {0.5, 0.02}, {0.8, 0.003}, {1.0, 0.001}, {0.3, 0.5}};
    size_t chosen = 99;
    CHECK_INT_EQ(halo_budget_choose(rows, 5, 1.0 / 255.0, &chosen, NULL), HALO_OK);
    CHECK_INT_EQ((int)chosen, 2);
    CHECK_INT_EQ(halo_budget_choose(rows, 5, 1.0, &chosen, NULL), HALO_OK);
    CHECK_INT_EQ((int)chosen, 4);
    /* a bound of 0: only the exact reference */
    CHECK_INT_EQ(halo_budget_choose(rows, 5, 0.0, &chosen, NULL), HALO_OK);
    CHECK_INT_EQ((int)chosen, 0);
    return 0;
}

static int test_ties_and_unmeasured(void)
{
    /* NaN and infinite errors or times never qualify; equal times: the smaller error */
    const halo_budget_row rows[] = {{NAN, 0.0}, {0.1, NAN}, {INFINITY, 0.0}, {-1.0, 0.0}, {1.0, 0.002}, {1.0, 0.001}};
    size_t chosen = 99;
    CHECK_INT_EQ(halo_budget_choose(rows, 6, 0.01, &chosen, NULL), HALO_OK);
    CHECK_INT_EQ((int)chosen, 5);
    return 0;
}

static int test_nothing_fits(void)
{
    const halo_budget_row rows[] = {{1.0, 0.1}, {2.0, 0.05}};
    size_t chosen = 99;
    halo_diagnostics *d = halo_diagnostics_create();
    CHECK_INT_EQ(halo_budget_choose(rows, 2, 0.01, &chosen, d), HALO_ERROR_INPUT);
    CHECK_DIAG(d, HALO_MSG_USAGE);
    CHECK_INT_EQ((int)chosen, 99); /* untouched */
    halo_diagnostics_clear(d);
    CHECK_INT_EQ(halo_budget_choose(rows, 2, NAN, &chosen, d), HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_budget_choose(rows, 2, -1.0, &chosen, d), HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_budget_choose(rows, 0, 1.0, &chosen, d), HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_budget_choose(NULL, 2, 1.0, &chosen, d), HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_budget_choose(rows, 2, 1.0, NULL, d), HALO_ERROR_INPUT);
    halo_diagnostics_destroy(d);
    return 0;
}

int main(void)
{
    RUN_TEST(test_cheapest_within);
    RUN_TEST(test_ties_and_unmeasured);
    RUN_TEST(test_nothing_fits);
    return check_exit_status();
}
