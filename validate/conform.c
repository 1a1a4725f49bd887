/* halo-validate conform: walks the registry of rows (conform_rows.c) with the harness
 * (conform_harness.c): each row's family function renders and compares it. --list
 * prints the registry instead. Tolerances and their reasons: the registry and
 * docs/accuracy.md. */
#include "conform.h"
#include "conform_harness.h"
#include "conform_rows.h"

#include <stdio.h>
#include <string.h>

/* One line per registry row: name, family, tolerance, what it renders, and why. */
static void list_rows(void)
{
    printf("%-22s %-8s %-17s %s\n", "row", "family", "tolerance", "renders; why the tolerance");
    for (size_t i = 0; i < conform_row_count; ++i) {
        const conform_row *r = &conform_rows[i];
        char tolerance[64];
        conform_tolerance_text(r, tolerance, sizeof tolerance);
        printf("%-22s %-8s %-17s %s\n%-49s %s\n", r->name, r->family, tolerance, r->renders, "", r->why);
    }
}

int halo_conform_main(int argc, char **argv)
{
    conform c = {.registry = conform_rows, .registry_count = conform_row_count};
    int status = conform_parse_command_line(&c, argc, argv);
    if (status >= 0)
        return status;
    if (c.list) {
        list_rows();
        return 0;
    }
    if (!conform_open(&c)) {
        conform_close(&c);
        return 2;
    }
    print_header();
    for (size_t i = 0; i < conform_row_count; ++i)
        conform_rows[i].run(&c, &conform_rows[i]);
    if (c.skipped)
        printf("%d rows, %d failed, %d skipped on OpenGL ES\n", c.rows, c.failures, c.skipped);
    else
        printf("%d rows, %d failed\n", c.rows, c.failures);
    status = c.failures ? 1 : 0;
    conform_close(&c);
    return status;
}
