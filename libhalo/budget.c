/* The error budget (halo.h): the cheapest measured configuration within an error bound. */
#include "halo.h"

#include "diag.h"

#include <math.h>

halo_status halo_budget_choose(const halo_budget_row *rows, size_t count, double max_error, size_t *chosen,
                               halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, rows, "rows", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, chosen, "chosen", HALO_ERROR_INPUT);
    if (count == 0) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_budget_choose: no rows (count is 0)");
        return HALO_ERROR_INPUT;
    }
    if (!(max_error >= 0.0)) { /* also rejects NaN */
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_budget_choose: the error bound %g is not a number >= 0",
                        max_error);
        return HALO_ERROR_INPUT;
    }
    size_t best = count;
    for (size_t i = 0; i < count; ++i) {
        const halo_budget_row *r = &rows[i];
        /* a row whose time or error was not measured (NaN, infinite, negative) never qualifies */
        if (!isfinite(r->seconds) || !isfinite(r->error) || r->seconds < 0.0 || r->error < 0.0 || r->error > max_error)
            continue;
        if (best == count || r->seconds < rows[best].seconds ||
            (r->seconds == rows[best].seconds && r->error < rows[best].error))
            best = i;
    }
    if (best == count) {
        double smallest = INFINITY;
        for (size_t i = 0; i < count; ++i)
            if (isfinite(rows[i].error) && rows[i].error >= 0.0 && rows[i].error < smallest)
                smallest = rows[i].error;
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_budget_choose: no configuration stays within the error bound %g (smallest measured "
                        "error: %g)",
                        max_error, smallest);
        return HALO_ERROR_INPUT;
    }
    *chosen = best;
    return HALO_OK;
}
