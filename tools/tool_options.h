/* The tools' command lines (halo-render, halo-view, halo-lines, halo-feature,
 * halo-outline): one walk over argv against a table of options, and the value parsers,
 * so that every tool says the same thing the same way: "TOOL: error: OPTION: ...". */
#ifndef HALO_TOOL_OPTIONS_H
#define HALO_TOOL_OPTIONS_H

#include <stdio.h>
#include <string.h>

/* One option: its name, another spelling (or NULL), and whether it takes a value. A
 * table ends with a zero entry. */
typedef struct halo_tool_option {
    const char *name, *alias;
    int valued;
} halo_tool_option;

typedef struct halo_tool_args {
    const char *tool;      /* the messages' prefix: "halo-render" */
    void (*usage)(FILE *); /* --help prints it on stdout; a usage error on stderr */
    int argc;
    char **argv;
    int next;           /* the argv index read next: 1 for a command, more after a subcommand */
    const char *option; /* the option just read, as written */
    const char *value;  /* its value (valued options), else NULL */
} halo_tool_args;

enum {
    HALO_TOOL_ARGS_END = -1,  /* argv is read */
    HALO_TOOL_ARGS_HELP = -2, /* --help or -h: the usage is printed on stdout (exit 0) */
    HALO_TOOL_ARGS_ERROR = -3 /* an unknown option or a missing value: said on stderr with the usage (exit 2) */
};

/* The index in table of the next option (its value in a->value), or one of the above. */
int halo_tool_args_next(halo_tool_args *a, const halo_tool_option *table);

/* Value parsers: 1 with *out set, or 0 after one message on stderr. */
int halo_tool_number(const char *tool, const char *option, const char *text, double lo, double hi, double *out);
int halo_tool_long(const char *tool, const char *option, const char *text, long lo, long hi, long *out);
int halo_tool_int(const char *tool, const char *option, const char *text, int lo, int hi, int *out);
/* "AsepBsepC": count parts of at most 63 characters each. */
int halo_tool_split(const char *tool, const char *option, const char *text, char separator, int count,
                    char parts[][64]);
/* "WxH", each side 1..max. */
int halo_tool_size(const char *tool, const char *option, const char *text, int max, int *width, int *height);
/* One of names (a NULL-terminated list): its index in *out. The message lists them. */
int halo_tool_choice(const char *tool, const char *option, const char *text, const char *const *names, int *out);

/* A file embedded by build-aux/embed.sh (tools/embedded_scenes.c: the built-in scenes,
 * examples/scenes/default.json and feature-default.json). */
struct halo_embedded_file {
    const char *name;
    const char *text;
};
extern const struct halo_embedded_file halo_embedded_scenes[];
/* The text of the embedded scene `name` ("examples/scenes/default.json"), or NULL. Only
 * for tools linked with tools/embedded_scenes.c (inline: the others never reference it). */
static inline const char *halo_tool_embedded_scene(const char *name)
{
    for (const struct halo_embedded_file *f = halo_embedded_scenes; f->name; ++f)
        if (!strcmp(f->name, name))
            return f->text;
    return NULL;
}

#endif
