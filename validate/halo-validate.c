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

#define EXIT_INPUT 1
#define EXIT_USAGE 2

static const char usage_text[] =
    "usage: halo-validate COMMAND [OPTIONS]\n"
    "\n"
    "commands:\n"
    "  check [--target T] [--error-limit N] FILE...\n"
    "                                 validate modules ('#pragma halo module', or .glsl),\n"
    "                                 hosts ('#pragma halo declarations': linked with no\n"
    "                                 stage) and shaders (.frag, .vert) for each target\n"
    "                                 (default: 330, 450 and es300)\n"
    "  link --scene S --host H [--target T] [--module FILE]... [-o OUT] [--reflect]\n"
    "       [--error-limit N]\n"
    "                                 link the scene's stages into the host shader and\n"
    "                                 validate; --reflect prints the reflection as JSON\n"
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
    "targets: 330 (GLSL 330 core), 450 (GLSL 450 core), es300 (GLSL ES 300)\n"
    "--error-limit N: show at most N errors per file and target, then how many more\n"
    "                 there were (default 100; 0: no limit)\n"
    "exit status: 0 success, 1 the input has errors, 2 usage or I/O failure\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "halo-validate: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'halo-validate --help'.\n");
    return EXIT_USAGE;
}

/* Maps a set of diagnostics to an exit status: I/O problems are 2, others 1. */
static int status_of(const halo_diagnostics *d) {
    int status = 0;
    for (size_t i = 0; i < halo_diagnostics_count(d); i++) {
        const halo_diagnostic *g = halo_diagnostics_get(d, i);
        if (g->severity != HALO_SEVERITY_ERROR) continue;
        if (g->id == HALO_MSG_IO_READ || g->id == HALO_MSG_IO_WRITE || g->id == HALO_MSG_OUT_OF_MEMORY) return EXIT_USAGE;
        status = EXIT_INPUT;
    }
    return status;
}

/* --error-limit N: the cap on the errors shown (halo_diagnostics_set_limit). */
static int parse_error_limit(const char *arg, size_t *limit) {
    char *end = NULL;
    errno = 0;
    unsigned long long n = arg && *arg >= '0' && *arg <= '9' ? strtoull(arg, &end, 10) : 0;
    if (!end || *end || errno || n > (unsigned long long)SIZE_MAX) return -1;
    *limit = (size_t)n;
    return 0;
}

static const char *extension(const char *path) {
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash : path, '.');
    return dot ? dot + 1 : "";
}

/* Reads a shader. NULL with *status EXIT_USAGE when the file cannot be read, or
 * EXIT_INPUT when it is no text (a NUL byte: an error in the input, at its place). */
static char *read_text(const char *path, int *status) {
    *status = EXIT_USAGE;
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "%s: error: cannot read: %s\n", path, strerror(errno));
        return NULL;
    }
    size_t cap = 65536, len = 0;
    char *buf = malloc(cap);
    for (size_t n; buf && (n = fread(buf + len, 1, cap - len - 1, f)) > 0;) {
        len += n;
        if (len + 1 == cap) {
            char *p = realloc(buf, cap *= 2);
            if (!p) { free(buf); buf = NULL; }
            else buf = p;
        }
    }
    int err = ferror(f);
    fclose(f);
    if (!buf || err) {
        fprintf(stderr, "%s: error: cannot read: %s\n", path, err ? "read error" : "out of memory");
        free(buf);
        return NULL;
    }
    buf[len] = '\0';
    const char *nul = memchr(buf, '\0', len);
    if (nul) {
        int line = 1, column = 1;
        for (const char *p = buf; p < nul; p++) {
            if (*p == '\n') { line++; column = 1; }
            else column++;
        }
        fprintf(stderr, "%s:%d:%d: error: the file contains a NUL byte; not a text shader\n", path, line, column);
        free(buf);
        *status = EXIT_INPUT;
        return NULL;
    }
    *status = 0;
    return buf;
}

static int parse_targets(const char *arg, halo_target *targets, int *count) {
    if (!strcmp(arg, "all")) {
        *count = 0;
        for (int t = HALO_TARGET_GLSL330; t < HALO_TARGET_COUNT; t++) targets[(*count)++] = (halo_target)t;
        return 0;
    }
    halo_target t = halo_target_from_name(arg);
    if (t == HALO_TARGET_COUNT) return -1;
    targets[0] = t;
    *count = 1;
    return 0;
}

static int cmd_check(int argc, char **argv) {
    halo_target targets[HALO_TARGET_COUNT];
    int ntargets = 0;
    parse_targets("all", targets, &ntargets);
    int nfiles = 0, worst = 0;
    size_t error_limit = HALO_DIAGNOSTICS_DEFAULT_LIMIT;
    char **files = calloc((size_t)argc + 1, sizeof *files);
    if (!files) return EXIT_USAGE;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--error-limit")) {
            if (i + 1 >= argc || parse_error_limit(argv[++i], &error_limit)) {
                free(files);
                return usage_error("--error-limit takes a number of errors (0: no limit)%s", "");
            }
        } else if (!strcmp(argv[i], "--target")) {
            if (i + 1 >= argc || parse_targets(argv[++i], targets, &ntargets)) {
                free(files);
                return usage_error("--target takes 330, 450, es300 or all", "");
            }
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
        } else if (module) {
            halo_status st = halo_library_override_file(lib, path, d);
            if (st != HALO_OK) {
                file_status = st == HALO_ERROR_IO ? EXIT_USAGE : EXIT_INPUT;
            } else {
                const halo_module *m = NULL;
                for (size_t i = 0; i < halo_library_module_count(lib); i++)
                    if (!strcmp(halo_module_file(halo_library_module(lib, i)), path)) m = halo_library_module(lib, i);
                for (int t = 0; m && t < ntargets; t++) {
                    if (halo_module_validate(lib, m, targets[t], d) == HALO_OK) continue;
                    fprintf(stderr, "%s: for target %s:\n", path, halo_target_name(targets[t]));
                    halo_diagnostics_print(d, stderr);
                    int s = status_of(d);
                    if (s > file_status) file_status = s;
                    halo_diagnostics_clear(d);
                }
            }
        } else if (shader) {
            for (int t = 0; t < ntargets; t++) {
                if (halo_validate_shader(text, path, !strcmp(ext, "vert") ? HALO_SHADER_VERTEX : HALO_SHADER_FRAGMENT,
                                         targets[t], d) == HALO_OK)
                    continue;
                fprintf(stderr, "%s: for target %s:\n", path, halo_target_name(targets[t]));
                halo_diagnostics_print(d, stderr);
                int s = status_of(d);
                if (s > file_status) file_status = s;
                halo_diagnostics_clear(d);
            }
        } else {
            fprintf(stderr,
                    "%s: error: unknown file type '.%s' (.glsl module, .frag or .vert shader, or a file with "
                    "'#pragma halo module' or '#pragma halo declarations')\n",
                    path, ext);
            file_status = EXIT_USAGE;
        }
        free(text);
        halo_diagnostics_print(d, stderr);
        int s = status_of(d);
        if (s > file_status) file_status = s;
        if (!file_status) {
            printf("%s: ok (", path);
            for (int t = 0; t < ntargets; t++) printf("%s%s", t ? ", " : "", halo_target_name(targets[t]));
            printf(")\n");
        }
        if (file_status > worst) worst = file_status;
    }
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    free(files);
    return worst;
}

static int cmd_link(int argc, char **argv) {
    const char *scene_path = NULL, *host_path = NULL, *out_path = NULL;
    int reflect = 0, nmodules = 0;
    size_t error_limit = HALO_DIAGNOSTICS_DEFAULT_LIMIT;
    halo_target target = HALO_TARGET_GLSL330;
    const char **modules = calloc((size_t)argc + 1, sizeof *modules);
    if (!modules) return EXIT_USAGE;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (!strcmp(a, "--scene") && has_value) scene_path = argv[++i];
        else if (!strcmp(a, "--host") && has_value) host_path = argv[++i];
        else if (!strcmp(a, "-o") && has_value) out_path = argv[++i];
        else if (!strcmp(a, "--module") && has_value) modules[nmodules++] = argv[++i];
        else if (!strcmp(a, "--reflect")) reflect = 1;
        else if (!strcmp(a, "--error-limit") && has_value) {
            if (parse_error_limit(argv[++i], &error_limit)) {
                free(modules);
                return usage_error("--error-limit takes a number of errors (0: no limit), not '%s'", argv[i]);
            }
        }
        else if (!strcmp(a, "--target") && has_value) {
            target = halo_target_from_name(argv[++i]);
            if (target == HALO_TARGET_COUNT) {
                free(modules);
                return usage_error("--target takes 330, 450 or es300, not '%s'", argv[i]);
            }
        } else {
            free(modules);
            return usage_error("link: unknown option or missing value: '%s'", a);
        }
    }
    if (!host_path) {
        free(modules);
        return usage_error("link needs --host FILE%s", "");
    }
    halo_diagnostics *d = halo_diagnostics_create();
    halo_diagnostics_set_limit(d, error_limit);
    halo_library *lib = halo_library_create(d);
    halo_scene *scene = NULL;
    halo_program *p = NULL;
    char *host = NULL;
    int status = 0;
    for (int i = 0; lib && i < nmodules; i++) halo_library_override_file(lib, modules[i], d);
    if (!lib || halo_diagnostics_errors(d)) goto done;
    scene = scene_path ? halo_scene_load(scene_path, lib, d) : halo_scene_create(lib);
    if (!scene) goto done;
    host = read_text(host_path, &status);
    if (!host) goto done;
    const char *ext = extension(host_path);
    p = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = host, .host_file = host_path,
                                    .target = target,
                                    .kind = !strcmp(ext, "vert") ? HALO_SHADER_VERTEX : HALO_SHADER_FRAGMENT},
                  d);
    if (!p || halo_program_validate(p, d) != HALO_OK) goto done;
    if (out_path) {
        FILE *f = fopen(out_path, "w");
        if (!f || fputs(halo_program_source(p), f) < 0 || fclose(f)) {
            fprintf(stderr, "%s: error: cannot write: %s\n", out_path, strerror(errno));
            status = EXIT_USAGE;
            goto done;
        }
    } else if (!reflect) {
        fputs(halo_program_source(p), stdout);
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
    if (!status) status = status_of(d);
    if (!status && !p) status = EXIT_INPUT;
    halo_program_destroy(p);
    free(host);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    free(modules);
    return status;
}

static int cmd_list(void) {
    halo_diagnostics *d = halo_diagnostics_create();
    halo_library *lib = halo_library_create(d);
    if (!lib) {
        halo_diagnostics_print(d, stderr);
        halo_diagnostics_destroy(d);
        return EXIT_USAGE;
    }
    static const char *const hooks[] = {"sample", "image", "line_vertex", "line_fragment"};
    for (size_t i = 0; i < halo_library_module_count(lib); i++) {
        const halo_module *m = halo_library_module(lib, i);
        printf("%-18s %-8s %s\n    %s\n", halo_module_name(m), hooks[halo_module_hook(m)], halo_module_file(m),
               halo_module_summary(m));
        for (size_t k = 0; k < halo_module_param_count(m); k++) {
            const halo_param_info *pi = halo_module_param(m, k);
            printf("    %-10s %-6s", pi->name, pi->type == HALO_PARAM_FLOAT ? "float" : "");
            printf(" [%g, %g] %s\n", pi->min, pi->max, pi->meaning);
        }
    }
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

int main(int argc, char **argv) {
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
    /* the commands that render take --backend (libhalo/gl/headless.h) */
    if ((!strcmp(cmd, "conform") || !strcmp(cmd, "bench") || !strcmp(cmd, "blur")) &&
        !halo_headless_take_backend_option(&argc, argv, "halo-validate")) {
        halo_shutdown();
        return EXIT_USAGE;
    }
    int status;
    if (!strcmp(cmd, "check")) status = cmd_check(argc - 1, argv + 1);
    else if (!strcmp(cmd, "link")) status = cmd_link(argc - 1, argv + 1);
    else if (!strcmp(cmd, "list")) status = cmd_list();
    else if (!strcmp(cmd, "conform")) status = halo_conform_main(argc - 1, argv + 1);
    else if (!strcmp(cmd, "bench")) status = halo_bench_main(argc - 1, argv + 1);
    else if (!strcmp(cmd, "blur")) status = halo_blur_report_main(argc - 1, argv + 1);
    else status = usage_error("unknown command '%s'", cmd);
    halo_shutdown();
    return status;
}
