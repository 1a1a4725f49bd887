/* See json_file.h. */
#include "json_file.h"

#include <stdio.h>
#include <string.h>

json_t *halo_json_load_file(const char *path, size_t flags, json_error_t *error)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return json_load_file(path, flags, error); /* its error text names the file */
    unsigned char mark[3];
    size_t got = fread(mark, 1, sizeof mark, f);
    if (got != sizeof mark || memcmp(mark, "\xEF\xBB\xBF", sizeof mark))
        rewind(f);
    json_t *root = json_loadf(f, flags, error);
    fclose(f);
    return root;
}
