/* See json_file.h. */
#include "json_file.h"

#include "halo.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

json_t *halo_json_load_file(const char *path, size_t flags, json_error_t *error)
{
    size_t len = 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    char *text = halo_read_text_file(path, "JSON file", &len, diag); /* bounded as libhalo's scenes */
    if (!text) {
        if (error) {
            const halo_diagnostic *why = halo_diagnostics_get(diag, 0);
            memset(error, 0, sizeof *error);
            error->line = error->column = -1;
            snprintf(error->source, sizeof error->source, "%s", path);
            snprintf(error->text, sizeof error->text, "%s", why ? why->text : "cannot read the file");
        }
        halo_diagnostics_destroy(diag);
        return NULL;
    }
    halo_diagnostics_destroy(diag);
    const char *start = len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3) ? text + 3 : text; /* a UTF-8 BOM */
    json_t *root = json_loadb(start, len - (size_t)(start - text), flags, error);
    free(text);
    return root;
}
