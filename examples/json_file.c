/* See json_file.h. */
#include "json_file.h"

#include "halo.h"
#include "strbuf.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

json_t *halo_json_load_file(const char *path, size_t flags, json_error_t *error)
{
    size_t len = 0;
    char *text = halo_read_file(path, &len); /* bounded as libhalo's scene reader is */
    if (!text) {
        if (error) {
            int e = errno;
            memset(error, 0, sizeof *error);
            error->line = error->column = -1;
            snprintf(error->source, sizeof error->source, "%s", path);
            if (e == EFBIG)
                snprintf(error->text, sizeof error->text,
                         "the file is larger than the %zu MiB that libhalo reads (HALO_MAX_FILE_BYTES)",
                         HALO_MAX_FILE_BYTES >> 20);
            else
                snprintf(error->text, sizeof error->text, "cannot read: %s", strerror(e));
        }
        return NULL;
    }
    const char *start = halo_skip_bom(text);
    json_t *root = json_loadb(start, len - (size_t)(start - text), flags, error);
    free(text);
    return root;
}
