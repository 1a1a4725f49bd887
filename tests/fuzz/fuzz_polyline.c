/* Fuzz target: the polyline reader (examples/linegen.c, docs/polyline-format.md) on
 * arbitrary text, and the writer on what it accepted (written to /dev/null). */
#include "fuzz.h"
#include "halo.h"
#include "linegen.h"

#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    if (!text)
        return 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_polylines lines = {0};
    if (halo_polylines_parse(text, "fuzz.txt", &lines, diag) == HALO_OK)
        halo_polylines_write("/dev/null", &lines);
    halo_polylines_free(&lines);
    halo_diagnostics_destroy(diag);
    free(text);
    return 0;
}
