/* halo-validate: the command-line front end of libhalo.
 * Exit status: 0 success, 1 the input has errors (diagnostics on stderr), 2 usage or I/O. */
#include "bench.h"
#include "blur_report.h"
#include "conform.h"
#include "halo.h"
#include "gl/headless.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define EXIT_INPUT 1
#define EXIT_USAGE 2

static const char usage_text[] =
    "usage: halo-validate COMMAND [OPTIONS]\n"
    "\n"
    "commands:\n"
    "  check [--target T] [--error-limit N] FILE...\n"
    "                                 validate modules ('#pragma halo module', or .glsl),\n"
    "                                 hosts ('#pragma halo declarations': linked with no\n"
    "                                 stage) for each target (default: 330, 450 and\n"
    "                                 es300), and plain shaders (.frag, .vert) as they\n"
    "                                 are: for their own #version (none: GLSL ES 1.00)\n"
    "                                 unless --target is given\n"
    "  link --scene S --host H [--target T] [--module FILE]... [-o OUT] [--reflect]\n"
    "       [--version target|keep|none] [--engine-uniforms] [--unlocated-outputs]\n"
    "       [--error-limit N]\n"
    "                                 link the scene's stages into the host shader and\n"
    "                                 validate; --reflect prints the reflection as JSON\n"
    "  link --pieces --scene S [--sample NAME=EXPR]... [--segmented]\n"
    "       [--pieces-dir DIR] [--composed FILE] [options of link]\n"
    "                                 link without host text, for shader composers\n"
    "                                 (docs/composers.md): print the declarations,\n"
    "                                 sample and finish pieces (to -o FILE, or write\n"
    "                                 DIR/NAME.glsl); each EXPR is one GLSL expression;\n"
    "                                 --composed validates the shader an engine composed\n"
    "  list                           list the stages with their parameters\n"
    "  conform [--stage NAME] [--size N] [-v]\n"
    "                                 render each stage headless and compare it with its\n"
    "                                 C emulation; one row per stage\n"
    "  bench [--size N] [--volume-size N] [--repeat R] [--table1]\n"
    "                                 frame time with and without halos, and the error\n"
    "                                 of each approximation against the exact reference\n"
    "  blur [--size N] [--repeat R] [--kernels K,...]\n"
    "                                 Gaussian blur of the outlines: error and time of\n"
    "                                 direct, separable and linear-sampled kernels\n"
    "  --help, --version\n"
    "\n"
    "conform, bench and blur render headless: --backend B chooses egl, osmesa or auto\n"
    "(default auto: EGL when it has a hardware renderer, else OSMesa)\n"
    "targets: 330 (GLSL 330 core), 450 (GLSL 450 core), es300 (GLSL ES 300),\n"
    "         150 (GLSL 150 core: outputs bound by name), all (330, 450, es300);\n"
    "         link's default is 330\n"
    "--error-limit N: show at most N errors per file, then how many more\n"
    "                 there were (default 100; 0: no limit); an error found for several\n"
    "                 targets prints once, naming them: [330, 450, es300]\n"
    "exit status: 0 success, 1 the input has errors, 2 usage or I/O failure\n";

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "halo-validate: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'halo-validate --help'.\n");
    return EXIT_USAGE;
}

/* Maps a set of diagnostics to an exit status: I/O problems are 2, others 1. */
static int status_of(const halo_diagnostics *d)
{
    int status = 0;
    for (size_t i = 0; i < halo_diagnostics_describe(d).count; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(d, i);
        if (g->severity != HALO_SEVERITY_ERROR)
            continue;
        if (g->id == HALO_MSG_IO_READ || g->id == HALO_MSG_IO_WRITE || g->id == HALO_MSG_OUT_OF_MEMORY ||
            g->id == HALO_MSG_INPUT_TOO_LARGE)
            return EXIT_USAGE;
        status = EXIT_INPUT;
    }
    return status;
}

/* --error-limit N: the cap on the errors shown (halo_diagnostics_set_limit). */
static int parse_error_limit(const char *arg, size_t *limit)
{
    char *end = NULL;
    errno = 0;
    unsigned long long n = arg && *arg >= '0' && *arg <= '9' ? strtoull(arg, &end, 10) : 0;
    if (!end || *end || errno || n > (unsigned long long)SIZE_MAX)
        return -1;
    *limit = (size_t)n;
    return 0;
}

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash : path, '.');
    return dot ? dot + 1 : "";
}

/* Reads a shader as libhalo reads its files (halo_read_text_file). NULL, with the message
 * on stderr, and *status EXIT_INPUT when the file is no text (a NUL byte: an error in the
 * input, at its place), else EXIT_USAGE (it cannot be read). */
static char *read_text(const char *path, int *status)
{
    halo_diagnostics *d = halo_diagnostics_create();
    char *text = d ? halo_read_text_file(path, "file", NULL, d) : NULL;
    *status = !text && halo_diagnostics_has(d, HALO_MSG_INPUT_NUL_BYTE) ? EXIT_INPUT : text ? 0 : EXIT_USAGE;
    if (!d)
        fprintf(stderr, "%s: error: cannot read: out of memory\n", path);
    halo_diagnostics_print(d, stderr);
    halo_diagnostics_destroy(d);
    return text;
}

static int parse_targets(const char *arg, halo_target *targets, int *count)
{
    if (!strcmp(arg, "all")) {
        *count = 0;
        /* 150 only when asked: hosts written for 330 and up declare layout(location) */
        for (int t = HALO_TARGET_GLSL330; t < HALO_TARGET_COUNT; t++)
            if (t != HALO_TARGET_GLSL150)
                targets[(*count)++] = (halo_target)t;
        return 0;
    }
    halo_target t = halo_target_from_name(arg);
    if (t == HALO_TARGET_COUNT)
        return -1;
    targets[0] = t;
    *count = 1;
    return 0;
}

/* What check is asked for: the targets, and whether --target chose them (a plain shader
 * is otherwise checked for its own #version). */
typedef struct check_targets {
    halo_target list[HALO_TARGET_COUNT];
    int count, given;
} check_targets;

/* Is a file checked for its own #version (a plain shader, no --target): one compile, not
 * one per target? */
static int checks_own_version(const char *text, int module, const check_targets *ct)
{
    return !module && !ct->given && halo_source_kind_of(text) == HALO_SOURCE_SHADER;
}

/* What the signal that ended a compile says (0: no exit status). */
static const char *crash_reason(int sig) { return sig ? strsignal(sig) : "no exit status"; }

/* The error for a file on which the compiler crashed: an input error at the file. */
static void report_crash(halo_diagnostics *d, const char *path, int sig)
{
    char text[256];
    snprintf(text, sizeof text, "the GLSL compiler crashed on this file (%s)", crash_reason(sig));
    halo_diagnostics_report(d, HALO_SEVERITY_ERROR, HALO_MSG_GLSL_ERROR, path, 0, 0, NULL, "%s", text);
}

/* Validates one file that read_text has read; module says it is a module, shader a host
 * or a plain shader ('#include' is resolved against its folder). crashed (NULL: none):
 * the targets on which the compiler crashed, by index in ct (signal number + 1), reported
 * as such in place of a check. Returns its exit status. */
static int check_file(const char *path, const char *text, int module, halo_library *lib, const check_targets *ct,
                      const int *crashed, halo_diagnostics *d)
{
    int file_status, own = 0;
    if (module) {
        halo_status st = halo_library_add(lib, path, NULL, HALO_ADD_REPLACE, d);
        if (st != HALO_OK) {
            halo_diagnostics_print(d, stderr);
            return st == HALO_ERROR_IO ? EXIT_USAGE : EXIT_INPUT;
        }
        const halo_module *m = NULL;
        for (size_t i = 0; i < halo_library_describe(lib).module_count; i++)
            if (!strcmp(halo_module_describe(halo_library_describe(lib).modules[i]).file, path))
                m = halo_library_describe(lib).modules[i];
        for (int t = 0; m && t < ct->count; t++) { /* printed once below, naming the targets */
            halo_diagnostics_set_run(d, halo_target_name(ct->list[t]));
            if (crashed && crashed[t])
                report_crash(d, path, crashed[t] - 1);
            else
                halo_validate(&(halo_validate_desc){.module = m, .library = lib, .target = ct->list[t]}, d);
        }
    } else {
        /* a plain shader is checked for its own #version unless --target says otherwise */
        own = checks_own_version(text, module, ct);
        halo_shader_kind kind = !strcmp(extension(path), "vert") ? HALO_SHADER_VERTEX : HALO_SHADER_FRAGMENT;
        for (int t = 0; t < (own ? 1 : ct->count); t++) { /* printed once below, naming the targets */
            halo_target target = own ? HALO_TARGET_DEFAULT : ct->list[t];
            halo_diagnostics_set_run(d, own ? NULL : halo_target_name(target));
            if (crashed && crashed[t])
                report_crash(d, path, crashed[t] - 1);
            else
                halo_validate(&(halo_validate_desc){.source = text, .file = path, .kind = kind, .target = target}, d);
        }
    }
    int implied = 0;
    for (size_t i = 0; i < halo_diagnostics_describe(d).count; i++)
        if (halo_diagnostics_get(d, i)->id == HALO_MSG_GLSL_VERSION_IMPLIED)
            implied = 1;
    halo_diagnostics_print(d, stderr);
    file_status = status_of(d);
    if (!file_status && own) {
        printf("%s: ok (%s)\n", path, implied ? "GLSL ES 1.00: no #version" : "its own #version");
    } else if (!file_status) {
        printf("%s: ok (", path);
        for (int t = 0; t < ct->count; t++)
            printf("%s%s", t ? ", " : "", halo_target_name(ct->list[t]));
        printf(")\n");
    }
    return file_status;
}

/* check_file in a child process, quiet: printing nothing. Returns the child's exit status,
 * or -1 when it died, with the signal in *sig (0: none). */
static int check_in_child(const char *path, const char *text, int module, halo_library *lib, const check_targets *ct,
                          const int *crashed, int quiet, halo_diagnostics *d, int *sig)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid == 0) {
        if (quiet && (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)))
            _exit(EXIT_USAGE);
        int s = check_file(path, text, module, lib, ct, crashed, d);
        fflush(stdout);
        fflush(stderr);
        _exit(s);
    }
    if (pid < 0)
        return quiet ? 0 : check_file(path, text, module, lib, ct, crashed, d); /* no child: in process */
    int wstatus = 0;
    while (waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {}
    if (WIFEXITED(wstatus))
        return WEXITSTATUS(wstatus);
    *sig = WIFSIGNALED(wstatus) ? WTERMSIG(wstatus) : 0;
    return -1;
}

/* check_file in a child process: glslang 12 crashes on some inputs, and a validator must
 * survive its compiler, report the file and go on with the others. The child checks
 * every target in its copy of d, so an error found for several prints once, and prints
 * them itself: what comes back is its exit status. When it crashes on one of several
 * targets, each target is checked again alone (printing nothing) to find the ones that
 * crash, then the others are checked and printed with a crash error for those: the
 * errors of the targets that compile are not lost. */
static int check_file_isolated(const char *path, const char *text, int module, halo_library *lib,
                               const check_targets *ct, halo_diagnostics *d)
{
    int sig = 0, status = check_in_child(path, text, module, lib, ct, NULL, 0, d, &sig);
    if (status < 0 && ct->count > 1 && !checks_own_version(text, module, ct)) {
        int crashed[HALO_TARGET_COUNT] = {0}, compiled = 0;
        for (int t = 0; t < ct->count; t++) {
            check_targets one = {.list = {ct->list[t]}, .count = 1, .given = ct->given};
            int s = 0;
            if (check_in_child(path, text, module, lib, &one, NULL, 1, d, &s) < 0)
                crashed[t] = s + 1;
            else
                compiled = 1;
        }
        if (compiled)
            status = check_in_child(path, text, module, lib, ct, crashed, 0, d, &sig);
    }
    if (module) {
        /* the parent's library takes the module too, for the files after it */
        halo_diagnostics *ignored = halo_diagnostics_create();
        halo_library_add(lib, path, NULL, HALO_ADD_REPLACE, ignored);
        halo_diagnostics_destroy(ignored);
    }
    if (status >= 0)
        return status;
    fprintf(stderr, "%s: error: the GLSL compiler crashed on this file (%s)\n", path, crash_reason(sig));
    return EXIT_INPUT;
}

static int cmd_check(int argc, char **argv)
{
    check_targets ct = {.count = 0};
    parse_targets("all", ct.list, &ct.count);
    int nfiles = 0, worst = 0;
    size_t error_limit = HALO_DIAGNOSTICS_DEFAULT_LIMIT;
    char **files = calloc((size_t)argc + 1, sizeof *files);
    if (!files)
        return EXIT_USAGE;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--error-limit")) {
            if (i + 1 >= argc || parse_error_limit(argv[++i], &error_limit)) {
                free(files);
                return usage_error("--error-limit takes a number of errors (0: no limit)%s", "");
            }
        } else if (!strcmp(argv[i], "--target")) {
            if (i + 1 >= argc || parse_targets(argv[++i], ct.list, &ct.count)) {
                free(files);
                return usage_error("--target takes 330, 450, es300, 150 or all", "");
            }
            ct.given = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            free(files);
            return usage_error("check: unknown option '%s'", argv[i]);
        } else {
            files[nfiles++] = argv[i];
        }
    }
    if (!nfiles) {
        free(files);
        return usage_error("check needs at least one FILE%s", "");
    }
    halo_diagnostics *d = halo_diagnostics_create();
    halo_diagnostics_set_limit(d, error_limit);
    halo_library *lib = halo_library_create(d);
    if (!lib) {
        halo_diagnostics_print(d, stderr);
        halo_diagnostics_destroy(d);
        free(files);
        return EXIT_USAGE;
    }
    for (int f = 0; f < nfiles; f++) {
        const char *path = files[f], *ext = extension(path);
        halo_diagnostics_clear(d);
        int file_status = 0;
        /* A module or a host by its annotations, whatever the extension; else by the extension. */
        int read_status;
        char *text = read_text(path, &read_status);
        halo_source_kind kind = text ? halo_source_kind_of(text) : HALO_SOURCE_SHADER;
        int module = kind == HALO_SOURCE_MODULE || (kind == HALO_SOURCE_SHADER && !strcmp(ext, "glsl"));
        int shader = !module && (kind == HALO_SOURCE_HOST || !strcmp(ext, "frag") || !strcmp(ext, "vert"));
        if (!text) {
            file_status = read_status;
        } else if (module || shader) {
            file_status = check_file_isolated(path, text, module, lib, &ct, d);
        } else {
            fprintf(stderr,
                    "%s: error: unknown file type '.%s' (.glsl module, .frag or .vert shader, or a file with "
                    "'#pragma halo module' or '#pragma halo declarations')\n",
                    path, ext);
            file_status = EXIT_USAGE;
        }
        free(text);
        if (file_status > worst)
            worst = file_status;
    }
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    free(files);
    return worst;
}

/* --sample NAME=EXPR: an expression of halo_pieces_desc. */
static int set_piece_expression(halo_pieces_desc *d, char *arg)
{
    char *eq = strchr(arg, '=');
    if (!eq || eq == arg || !eq[1])
        return -1;
    *eq = '\0';
    const char *v = eq + 1;
    /* gradient_texture: the field's own name, as the diagnostics of an expression call it */
    static const char *const names[] = {
        "position",         "value",           "gradient", "view", "depth", "fragcoord", "color", "volume",
        "gradient-texture", "gradient_texture"};
    const char **fields[] = {&d->position,
                             &d->value,
                             &d->gradient,
                             &d->view,
                             &d->depth,
                             &d->fragcoord,
                             &d->color,
                             &d->volume,
                             &d->gradient_texture,
                             &d->gradient_texture};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(arg, names[i])) {
            *fields[i] = v;
            return 0;
        }
    *eq = '=';
    return -1;
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f || fputs(text, f) < 0 || fclose(f)) {
        fprintf(stderr, "%s: error: cannot write: %s\n", path, strerror(errno));
        return EXIT_USAGE;
    }
    return 0;
}

/* link --pieces: the pieces, with a header each, to stdout or to the file -o names, or
 * into DIR. */
static int print_pieces(const halo_program *p, const char *dir, const char *out_path)
{
    static const char *const names[HALO_PIECE_COUNT] = {"declarations", "sample", "finish"};
    if (!dir) {
        FILE *out = out_path ? fopen(out_path, "w") : stdout;
        int bad = !out;
        for (int k = 0; out && k < HALO_PIECE_COUNT; k++) {
            const char *text = halo_program_source(p, (halo_piece)k);
            bad |= fprintf(out, "// ==== libhalo piece: %s ====\n%s", names[k], text ? text : "") < 0;
        }
        if (out && out != stdout)
            bad |= fclose(out) != 0;
        if (bad)
            fprintf(stderr, "%s: error: cannot write: %s\n", out_path ? out_path : "<stdout>", strerror(errno));
        return bad ? EXIT_USAGE : 0;
    }
    for (int k = 0; k < HALO_PIECE_COUNT; k++) {
        const char *text = halo_program_source(p, (halo_piece)k);
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.glsl", dir, names[k]);
        int st = write_text(path, text ? text : "");
        if (st)
            return st;
    }
    return 0;
}

static int cmd_link(int argc, char **argv)
{
    const char *scene_path = NULL, *host_path = NULL, *out_path = NULL, *composed_path = NULL, *pieces_dir = NULL;
    const char *pieces_option = NULL; /* the last option that only pieces take */
    int reflect = 0, nmodules = 0, pieces = 0;
    size_t error_limit = HALO_DIAGNOSTICS_DEFAULT_LIMIT;
    halo_pieces_desc pd = {0};
    halo_link_desc desc = {.target = HALO_TARGET_GLSL330};
    const char **modules = calloc((size_t)argc + 1, sizeof *modules);
    if (!modules)
        return EXIT_USAGE;
    int bad = 0;
    for (int i = 1; i < argc && !bad; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (!strcmp(a, "--scene") && has_value)
            scene_path = argv[++i];
        else if (!strcmp(a, "--host") && has_value)
            host_path = argv[++i];
        else if (!strcmp(a, "-o") && has_value)
            out_path = argv[++i];
        else if (!strcmp(a, "--module") && has_value)
            modules[nmodules++] = argv[++i];
        else if (!strcmp(a, "--reflect"))
            reflect = 1;
        else if (!strcmp(a, "--pieces"))
            pieces = 1;
        else if (!strcmp(a, "--pieces-dir") && has_value)
            pieces = 1, pieces_dir = argv[++i];
        else if (!strcmp(a, "--composed") && has_value)
            pieces = 1, composed_path = argv[++i];
        else if (!strcmp(a, "--segmented"))
            pd.segmented = 1, pieces_option = a;
        else if (!strcmp(a, "--engine-uniforms"))
            desc.engine_uniforms = 1;
        else if (!strcmp(a, "--unlocated-outputs"))
            desc.output_locations = HALO_LOCATIONS_BY_NAME;
        else if (!strcmp(a, "--first-output-location") && has_value) {
            pieces_option = a;
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 15)
                bad = usage_error("--first-output-location takes 1..15, not '%s'", argv[i]);
            pd.first_output_location = (int)v;
        } else if (!strcmp(a, "--sample") && has_value) {
            pieces_option = a;
            if (set_piece_expression(&pd, argv[++i]))
                bad = usage_error(
                    "--sample takes NAME=EXPR with NAME position, value, gradient, view, depth, "
                    "fragcoord, color, volume or gradient-texture, not '%s'",
                    argv[i]);
        } else if (!strcmp(a, "--version") && has_value) {
            const char *v = argv[++i];
            if (!strcmp(v, "target"))
                desc.version = HALO_VERSION_TARGET;
            else if (!strcmp(v, "keep"))
                desc.version = HALO_VERSION_KEEP;
            else if (!strcmp(v, "none"))
                desc.version = HALO_VERSION_NONE;
            else
                bad = usage_error("--version takes target, keep or none, not '%s'", v);
        } else if (!strcmp(a, "--error-limit") && has_value) {
            if (parse_error_limit(argv[++i], &error_limit))
                bad = usage_error("--error-limit takes a number of errors (0: no limit), not '%s'", argv[i]);
        } else if (!strcmp(a, "--target") && has_value) {
            desc.target = halo_target_from_name(argv[++i]);
            if (desc.target == HALO_TARGET_COUNT)
                bad = usage_error("--target takes 330, 450, es300 or 150, not '%s'", argv[i]);
        } else {
            bad = usage_error("link: unknown option or missing value: '%s'", a);
        }
    }
    if (!bad && !host_path && !pieces)
        bad = usage_error("link needs --host FILE, or --pieces%s", "");
    if (!bad && host_path && pieces)
        bad = usage_error("link takes --host FILE or --pieces, not both%s", "");
    if (!bad && host_path && pieces_option)
        bad = usage_error("%s applies to --pieces only: a host shader's own text says it (not with --host)",
                          pieces_option);
    if (bad) {
        free(modules);
        return bad;
    }
    halo_diagnostics *d = halo_diagnostics_create();
    halo_diagnostics_set_limit(d, error_limit);
    halo_library *lib = halo_library_create(d);
    halo_scene *scene = NULL;
    halo_program *p = NULL;
    char *host = NULL, *composed = NULL;
    int status = 0;
    for (int i = 0; lib && i < nmodules; i++)
        halo_library_add(lib, modules[i], NULL, HALO_ADD_REPLACE, d);
    if (!lib || halo_diagnostics_describe(d).errors)
        goto done;
    scene = scene_path ? halo_scene_load(scene_path, NULL, lib, d) : halo_scene_create(lib);
    if (!scene)
        goto done;
    if (host_path) {
        host = read_text(host_path, &status);
        if (!host)
            goto done;
        desc.kind = !strcmp(extension(host_path), "vert") ? HALO_SHADER_VERTEX : HALO_SHADER_FRAGMENT;
    } else {
        desc.pieces = &pd;
    }
    if (composed_path && !(composed = read_text(composed_path, &status)))
        goto done;
    desc.library = lib;
    desc.scene = scene;
    desc.host_source = host;
    desc.host_file = host_path;
    p = halo_link(&desc, d);
    if (!p || halo_validate(&(halo_validate_desc){.program = p}, d) != HALO_OK)
        goto done;
    if (composed && halo_validate(&(halo_validate_desc){.program = p,
                                                        .composed = composed,
                                                        .composed_file = composed_path,
                                                        .composer_pieces = NULL,
                                                        .composer_piece_count = 0},
                                  d) != HALO_OK)
        goto done;
    if (pieces && (pieces_dir || !reflect)) {
        status = print_pieces(p, pieces_dir, out_path);
        if (status)
            goto done;
    } else if (out_path) {
        status = write_text(out_path, halo_program_source(p, HALO_PIECE_WHOLE));
        if (status)
            goto done;
    } else if (!reflect) {
        fputs(halo_program_source(p, HALO_PIECE_WHOLE), stdout);
    }
    if (reflect) {
        char *json = halo_program_reflect_json(p);
        if (!json) {
            status = EXIT_USAGE;
            goto done;
        }
        printf("%s\n", json);
        free(json);
    }
done:
    halo_diagnostics_print(d, stderr);
    if (!status)
        status = status_of(d);
    if (!status && !p)
        status = EXIT_INPUT;
    halo_program_destroy(p);
    free(host);
    free(composed);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    free(modules);
    return status;
}

static int cmd_list(void)
{
    halo_diagnostics *d = halo_diagnostics_create();
    halo_library *lib = halo_library_create(d);
    if (!lib) {
        halo_diagnostics_print(d, stderr);
        halo_diagnostics_destroy(d);
        return EXIT_USAGE;
    }
    static const char *const hooks[] = {"sample", "image", "line_vertex", "line_fragment"};
    for (size_t i = 0; i < halo_library_describe(lib).module_count; i++) {
        const halo_module *m = halo_library_describe(lib).modules[i];
        printf("%-18s %-8s %s\n    %s\n", halo_module_describe(m).name, hooks[halo_module_describe(m).hook],
               halo_module_describe(m).file, halo_module_describe(m).summary);
        for (size_t k = 0; k < halo_module_describe(m).param_count; k++) {
            const halo_param_info *pi = &halo_module_describe(m).params[k];
            printf("    %-10s %-6s", pi->name, pi->type == HALO_PARAM_FLOAT ? "float" : "");
            printf(" [%g, %g] %s\n", pi->min, pi->max, pi->meaning);
        }
    }
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage_text, stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h")) {
        fputs(usage_text, stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("halo-validate (libhalo) %s, host contract %d\n", halo_version(), HALO_CONTRACT_VERSION);
        return 0;
    }
    if (halo_setup(&(halo_setup_desc){0}) != HALO_OK) {
        fprintf(stderr, "halo-validate: error: glslang failed to initialize\n");
        return EXIT_USAGE;
    }
    /* the commands that render take --backend (libhalo/gl/headless.h); conform runs on
     * OpenGL ES too (the rows a host can run there) */
    halo_headless_allow_es(!strcmp(cmd, "conform"));
    if ((!strcmp(cmd, "conform") || !strcmp(cmd, "bench") || !strcmp(cmd, "blur")) &&
        !halo_headless_take_backend_option(&argc, argv, "halo-validate")) {
        halo_shutdown();
        return EXIT_USAGE;
    }
    int status;
    if (!strcmp(cmd, "check"))
        status = cmd_check(argc - 1, argv + 1);
    else if (!strcmp(cmd, "link"))
        status = cmd_link(argc - 1, argv + 1);
    else if (!strcmp(cmd, "list"))
        status = cmd_list();
    else if (!strcmp(cmd, "conform"))
        status = halo_conform_main(argc - 1, argv + 1);
    else if (!strcmp(cmd, "bench"))
        status = halo_bench_main(argc - 1, argv + 1);
    else if (!strcmp(cmd, "blur"))
        status = halo_blur_report_main(argc - 1, argv + 1);
    else
        status = usage_error("unknown command '%s'", cmd);
    halo_shutdown();
    return status;
}
