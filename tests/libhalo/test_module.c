/* Module annotations (docs/modules.md): parsing a valid module, and every error with
 * its message id at the right line. No GL, no glslang. */
#include "check.h"

static halo_library *library;
static halo_diagnostics *diags;

/* Adds a module from source; returns its status with the diagnostics in `diags`. */
static halo_status add(const char *file, const char *source)
{
    halo_diagnostics_clear(diags);
    return halo_library_add(library, file, source, HALO_ADD_NEW, diags);
}

static const char valid_module[] =
    "#pragma halo module every_type\n"                                                        /* 1 */
    "#pragma halo summary \"a parameter of every type\"\n"                                    /* 2 */
    "#pragma halo hook sample\n"                                                              /* 3 */
    "#pragma halo param a float default=0.5 min=0 max=1 \"a float (fraction)\"\n"             /* 4 */
    "#pragma halo param b vec2 default=[1,-2] min=-5 max=5 \"a vec2\"\n"                      /* 5 */
    "#pragma halo param c vec3 default=[0.1, 0.2, 0.3] \"a vec3 without a range\"\n"          /* 6 */
    "#pragma halo param d vec4 default=[1,2,3,4] min=0 max=10 \"a vec4\"\n"                   /* 7 */
    "#pragma halo param e int default=3 min=1 max=8 step=2 \"an int\"\n"                      /* 8 */
    "#pragma halo param f bool default=true \"a bool\"\n"                                     /* 9 */
    "#pragma halo param g float[4] default=[0.25,0.5] min=0 max=1 \"a float array\"\n"        /* 10 */
    "#pragma halo param h vec3[2] default=[[1,0,0],[0,1,-1]] min=-1 max=1 \"a vec3 array\"\n" /* 11 */
    "\n"                                                                                      /* 12 */
    "float weight(float x) { return x * a; }\n"                                               /* 13 */
    "void apply(inout halo_sample s)\n"                                                       /* 14 */
    "{\n"                                                                                     /* 15 */
    "    s.opacity = weight(s.opacity) + b.x + c.y + d.z + float(e) + (f ? 1.0 : 0.0) + g[0] + h[1].z\n"
    "              + float(g_count + h_count);\n"
    "}\n";

static int test_valid_module(void)
{
    size_t before = halo_library_describe(library).module_count;
    CHECK_INT_EQ(add("user/every_type.glsl", valid_module), HALO_OK);
    CHECK_NO_ERRORS(diags);
    CHECK_INT_EQ(halo_library_describe(library).module_count, before + 1);
    const halo_module *m = halo_library_find(library, "every_type");
    CHECK(m != NULL);
    CHECK_STR_EQ(halo_module_describe(m).name, "every_type");
    CHECK_STR_EQ(halo_module_describe(m).file, "user/every_type.glsl");
    CHECK_STR_EQ(halo_module_describe(m).summary, "a parameter of every type");
    CHECK_INT_EQ(halo_module_describe(m).hook, HALO_HOOK_SAMPLE);
    CHECK_INT_EQ(halo_module_describe(m).param_count, 8);

    const halo_param_info *p = &halo_module_describe(m).params[0];
    CHECK_STR_EQ(p->name, "a");
    CHECK_INT_EQ(p->type, HALO_PARAM_FLOAT);
    CHECK_INT_EQ(p->array_size, 0);
    CHECK_INT_EQ(p->components, 1);
    CHECK_NEAR(p->min, 0, 0);
    CHECK_NEAR(p->max, 1, 0);
    CHECK_INT_EQ(p->default_count, 1);
    CHECK_NEAR(p->default_value[0], 0.5, 0);
    CHECK_STR_EQ(p->meaning, "a float (fraction)");
    CHECK_NEAR(p->step, 0, 0); /* not stated */
    CHECK_NEAR(halo_module_find_param(m, "e")->step, 2, 0);

    p = halo_module_find_param(m, "b");
    CHECK(p == &halo_module_describe(m).params[1]);
    CHECK_INT_EQ(p->type, HALO_PARAM_VEC2);
    CHECK_INT_EQ(p->components, 2);
    CHECK_NEAR(p->min, -5, 0);
    CHECK_NEAR(p->max, 5, 0);
    CHECK_NEAR(p->default_value[0], 1, 0);
    CHECK_NEAR(p->default_value[1], -2, 0);

    p = halo_module_find_param(m, "c");
    CHECK_INT_EQ(p->type, HALO_PARAM_VEC3);
    CHECK_INT_EQ(p->components, 3);
    CHECK(p->min < -1e300 && p->max > 1e300); /* no range given: unbounded */
    CHECK_NEAR(p->default_value[2], 0.3, 0);

    p = halo_module_find_param(m, "d");
    CHECK_INT_EQ(p->type, HALO_PARAM_VEC4);
    CHECK_INT_EQ(p->components, 4);
    for (int i = 0; i < 4; i++)
        CHECK_NEAR(p->default_value[i], i + 1, 0);

    p = halo_module_find_param(m, "e");
    CHECK_INT_EQ(p->type, HALO_PARAM_INT);
    CHECK_NEAR(p->default_value[0], 3, 0);
    CHECK_NEAR(p->min, 1, 0);
    CHECK_NEAR(p->max, 8, 0);

    p = halo_module_find_param(m, "f");
    CHECK_INT_EQ(p->type, HALO_PARAM_BOOL);
    CHECK_NEAR(p->default_value[0], 1, 0);
    CHECK_NEAR(p->min, 0, 0); /* a bool is 0 or 1 */
    CHECK_NEAR(p->max, 1, 0);

    p = halo_module_find_param(m, "g");
    CHECK_INT_EQ(p->type, HALO_PARAM_FLOAT);
    CHECK_INT_EQ(p->array_size, 4);
    CHECK_INT_EQ(p->components, 1);
    CHECK_INT_EQ(p->default_count, 2);
    CHECK_NEAR(p->default_value[0], 0.25, 0);
    CHECK_NEAR(p->default_value[1], 0.5, 0);

    p = halo_module_find_param(m, "h");
    CHECK_INT_EQ(p->type, HALO_PARAM_VEC3);
    CHECK_INT_EQ(p->array_size, 2);
    CHECK_INT_EQ(p->components, 3);
    CHECK_INT_EQ(p->default_count, 2);
    static const double h[6] = {1, 0, 0, 0, 1, -1};
    for (int i = 0; i < 6; i++)
        CHECK_NEAR(p->default_value[i], h[i], 0);
    CHECK_NEAR(p->min, -1, 0);

    CHECK(halo_module_find_param(m, "nope") == NULL);
    CHECK(!halo_module_describe(m).has_emulation);
    return 0;
}

/* The embedded modules parse, with the parameters their files declare. */
static int test_builtin_modules(void)
{
    const halo_module *b = halo_library_find(library, "boundary");
    CHECK(b != NULL);
    CHECK_STR_EQ(halo_module_describe(b).file, "glsl/sample/boundary.glsl");
    const halo_param_info *k_gs = halo_module_find_param(b, "k_gs");
    CHECK(k_gs != NULL);
    CHECK_NEAR(k_gs->default_value[0], 10, 0);
    CHECK_NEAR(k_gs->min, 0, 0);
    CHECK_NEAR(k_gs->max, 1000, 0);
    const halo_module *t = halo_library_find(library, "tone_shading");
    CHECK(t != NULL);
    const halo_param_info *lights = halo_module_find_param(t, "lights");
    CHECK(lights != NULL);
    CHECK_INT_EQ(lights->array_size, 4);
    CHECK_INT_EQ(lights->default_count, 1);
    int stages = 0;
    for (size_t i = 0; i < halo_library_describe(library).module_count; i++) {
        const halo_module *m = halo_library_describe(library).modules[i];
        if (!strcmp(halo_module_describe(m).name, "halo_math") || strncmp(halo_module_describe(m).file, "glsl/", 5))
            continue;
        stages++;
        if (halo_module_describe(m).hook != HALO_HOOK_IMAGE && !halo_module_describe(m).has_emulation)
            CHECK_FAIL_AT("built-in stage %s has no emulation", halo_module_describe(m).name);
    }
    CHECK(stages >= 9);
    return 0;
}

/* One error: status, id, file and line. */
#define CHECK_ONE_ERROR(FILE_, SOURCE_, ID, LINE)                                 \
    do {                                                                          \
        size_t count_before_ = halo_library_describe(library).module_count;       \
        CHECK_INT_EQ(add(FILE_, SOURCE_), HALO_ERROR_INPUT);                      \
        CHECK_DIAG_LINE(diags, ID, LINE);                                         \
        CHECK_STR_EQ(check_find_diag(diags, ID, LINE)->file, FILE_);              \
        CHECK_INT_EQ(halo_library_describe(library).module_count, count_before_); \
    } while (0)

/* Each of the lines, put into a sample module after head (so at line `line`), is refused
 * with id at that line. */
static int check_each_line_refused(const char *file, const char *head, const char *const *lines, size_t count,
                                   halo_message_id id, int line)
{
    for (size_t i = 0; i < count; i++) {
        char source[512];
        snprintf(source, sizeof source, "%s%svoid apply(inout halo_sample s) {}\n", head, lines[i]);
        CHECK_INT_EQ(add(file, source), HALO_ERROR_INPUT);
        if (!check_find_diag(diags, id, line)) {
            check_print_diags(diags);
            CHECK_FAIL_AT("no %s at line %d for: %s", halo_message_name(id), line, lines[i]);
        }
    }
    return 0;
}

static int test_unknown_directive(void)
{
    CHECK_ONE_ERROR("user/unknown.glsl",
                    "#pragma halo module unknown_directive\n"
                    "#pragma halo hook sample\n"
                    "\n"
                    "#pragma halo frobnicate 3\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_UNKNOWN, 4);
    CHECK(halo_library_find(library, "unknown_directive") == NULL);
    /* The host's marker is no module annotation. */
    CHECK_ONE_ERROR("user/marker.glsl",
                    "#pragma halo module with_marker\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo declarations\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_UNKNOWN, 3);
    return 0;
}

static int test_malformed_param(void)
{
    static const char *const bad_lines[] = {
        "#pragma halo param\n",                                        /* no name */
        "#pragma halo param k_x\n",                                    /* no type */
        "#pragma halo param K_X float default=1\n",                    /* name not [a-z][a-z0-9_]* */
        "#pragma halo param k_x float default=1 bogus\n",              /* stray word */
        "#pragma halo param k_x float default=1 min=zero\n",           /* min not a number */
        "#pragma halo param k_x float default=1 min=2 max=1\n",        /* min above max */
        "#pragma halo param k_x float default=1 step=0\n",             /* step not above 0 */
        "#pragma halo param k_x float default=1 step=inf\n",           /* step not finite */
        "#pragma halo param k_x int default=1 step=0.5\n",             /* an int's step not whole */
        "#pragma halo param k_x float default=1 \"unclosed meaning\n", /* unclosed quote */
    };
    if (check_each_line_refused("user/malformed.glsl",
                                "#pragma halo module malformed\n"
                                "#pragma halo hook sample\n"
                                "// the next line is malformed\n",
                                bad_lines, sizeof bad_lines / sizeof bad_lines[0], HALO_MSG_ANNOTATION_SYNTAX, 4))
        return 1;
    /* A parameter without default= is missing a required part. */
    CHECK_INT_EQ(add("user/malformed.glsl",
                     "#pragma halo module no_default\n"
                     "#pragma halo hook sample\n"
                     "#pragma halo param k float min=0 max=1\n"
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_ERROR_INPUT);
    CHECK(halo_diagnostics_describe(diags).errors >= 1);
    CHECK(check_find_diag(diags, HALO_MSG_ANNOTATION_MISSING, 3) ||
          check_find_diag(diags, HALO_MSG_ANNOTATION_SYNTAX, 3));
    return 0;
}

static int test_unknown_type(void)
{
    CHECK_ONE_ERROR("user/type.glsl",
                    "#pragma halo module unknown_type\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param k mat3 default=1 \"no matrices\"\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_PARAM_TYPE_UNKNOWN, 3);
    /* Arrays: size 1..16, at most 64 numbers. */
    CHECK_ONE_ERROR("user/type.glsl",
                    "#pragma halo module big_array\n"
                    "#pragma halo hook sample\n"
                    "\n"
                    "#pragma halo param k vec4[17] default=[[0,0,0,0]]\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_PARAM_TYPE_UNKNOWN, 4);
    CHECK_ONE_ERROR("user/type.glsl",
                    "#pragma halo module zero_array\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param k float[0] default=[1]\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_PARAM_TYPE_UNKNOWN, 3);
    return 0;
}

static int test_default_invalid(void)
{
    static const char *const bad_lines[] = {
        "#pragma halo param k float default=5 min=0 max=1\n",         /* above max */
        "#pragma halo param k float default=-0.5 min=0 max=1\n",      /* below min */
        "#pragma halo param k vec3 default=[0,0,2] min=0 max=1\n",    /* one component above max */
        "#pragma halo param k vec3 default=[0,0] \"two of three\"\n", /* wrong component count */
        "#pragma halo param k float default=\"one\"\n",               /* not a number */
        "#pragma halo param k float default=[1\n",                    /* not JSON */
        "#pragma halo param k int default=1.5 min=0 max=4\n",         /* not a whole number */
        "#pragma halo param k bool default=2\n",                      /* a bool is 0 or 1 */
        "#pragma halo param k float[2] default=[1,2,3]\n",            /* too many elements */
    };
    return check_each_line_refused("user/default.glsl",
                                   "#pragma halo module bad_default\n"
                                   "#pragma halo hook sample\n",
                                   bad_lines, sizeof bad_lines / sizeof bad_lines[0], HALO_MSG_PARAM_DEFAULT_INVALID,
                                   3);
}

static int test_duplicate_param(void)
{
    CHECK_ONE_ERROR("user/dup.glsl",
                    "#pragma halo module duplicate_param\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param k float default=1\n"
                    "#pragma halo param j float default=1\n"
                    "#pragma halo param k vec3 default=[1,1,1]\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_PARAM_DUPLICATE, 5);
    return 0;
}

static int test_missing_annotations(void)
{
    /* No module (nor library). */
    CHECK_INT_EQ(add("user/anonymous.glsl",
                     "#pragma halo hook sample\n"
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_ANNOTATION_MISSING);
    CHECK_STR_EQ(check_find_diag(diags, HALO_MSG_ANNOTATION_MISSING, 0)->file, "user/anonymous.glsl");
    /* No hook: reported at the module line. */
    CHECK_ONE_ERROR("user/hookless.glsl",
                    "// a module without a hook\n"
                    "#pragma halo module hookless\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_MISSING, 2);
    /* An empty file. */
    CHECK_INT_EQ(add("user/empty.glsl", ""), HALO_ERROR_INPUT);
    CHECK_DIAG(diags, HALO_MSG_ANNOTATION_MISSING);
    /* Unknown hook; module given twice. */
    CHECK_ONE_ERROR("user/hook.glsl",
                    "#pragma halo module bad_hook\n"
                    "#pragma halo hook per_pixel\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_MODULE_HOOK_UNKNOWN, 2);
    CHECK_ONE_ERROR("user/twice.glsl",
                    "#pragma halo module twice\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo module again\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_DUPLICATE, 3);
    return 0;
}

static int test_entry_missing(void)
{
    CHECK_ONE_ERROR("user/no_apply.glsl",
                    "#pragma halo module no_apply\n"
                    "#pragma halo hook sample\n"
                    "void apply_later(inout halo_sample s) {}\n",
                    HALO_MSG_MODULE_ENTRY_MISSING, 1);
    return 0;
}

static int test_duplicate_module(void)
{
    static const char source[] =
        "#pragma halo module twin\n"
        "#pragma halo hook sample\n"
        "void apply(inout halo_sample s) {}\n";
    CHECK_INT_EQ(add("user/twin.glsl", source), HALO_OK);
    CHECK_ONE_ERROR("user/twin_again.glsl", source, HALO_MSG_MODULE_DUPLICATE, 1);
    /* A user module may not take a built-in stage's name with add_source. */
    CHECK_ONE_ERROR("user/boundary.glsl",
                    "#pragma halo module boundary\n"
                    "#pragma halo hook sample\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_MODULE_DUPLICATE, 1);
    CHECK_STR_EQ(halo_module_describe(halo_library_find(library, "boundary")).file, "glsl/sample/boundary.glsl");
    return 0;
}

static int test_reserved_name(void)
{
    CHECK_ONE_ERROR("user/reserved.glsl",
                    "#pragma halo module reserved\n"
                    "#pragma halo hook sample\n"
                    "\n"
                    "float halo_mine(float x) { return x; }\n"
                    "void apply(inout halo_sample s) { s.opacity = halo_mine(s.opacity); }\n",
                    HALO_MSG_MODULE_RESERVED_NAME, 4);
    CHECK_ONE_ERROR("user/reserved.glsl",
                    "#pragma halo module reserved_const\n"
                    "#pragma halo hook sample\n"
                    "const float halo_scale = 2.0;\n"
                    "void apply(inout halo_sample s) { s.opacity *= halo_scale; }\n",
                    HALO_MSG_MODULE_RESERVED_NAME, 3);
    /* Providing a field the host fills. */
    CHECK_ONE_ERROR("user/reserved.glsl",
                    "#pragma halo module provides_color\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo provides color vec3\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_MODULE_RESERVED_NAME, 3);
    /* Calling the shared helpers is allowed. */
    CHECK_INT_EQ(add("user/helper_user.glsl",
                     "#pragma halo module helper_user\n"
                     "#pragma halo hook sample\n"
                     "void apply(inout halo_sample s) { s.opacity = halo_saturate(s.opacity); }\n"),
                 HALO_OK);
    return 0;
}

/* '#pragma halo is': what a stage is, for hosts (halo_stage_info; issue 28) */
static int test_is_annotation(void)
{
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_unknown\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo is keeps_empty transparent\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 3);
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_empty\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo is\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 3);
    /* labels_when names a parameter of the module */
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_labels\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param label float default=-1 min=-1 max=100\n"
                    "#pragma halo is labels_when=lable\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 4);
    /* interval names an int parameter of the module */
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_interval\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param m float default=4\n"
                    "#pragma halo is interval=m\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 4);
    /* strip_width and core_fraction name a float scalar parameter; each property once */
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_width\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param w int default=4\n"
                    "#pragma halo is strip_width=w\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 4);
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_core\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param c float[2] default=[0.5]\n"
                    "#pragma halo is core_fraction=c\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 4);
    CHECK_ONE_ERROR("user/is.glsl",
                    "#pragma halo module is_twice\n"
                    "#pragma halo hook sample\n"
                    "#pragma halo param c float default=0.5\n"
                    "#pragma halo is core_fraction=c core_fraction=c\n"
                    "void apply(inout halo_sample s) {}\n",
                    HALO_MSG_ANNOTATION_SYNTAX, 4);
    CHECK_INT_EQ(add("user/is_lines.glsl",
                     "#pragma halo module is_lines\n"
                     "#pragma halo hook sample\n"
                     "#pragma halo param c float default=0.5\n"
                     "#pragma halo param w float default=0.1\n"
                     "#pragma halo is core_fraction=c strip_width=w\n"
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_OK);
    CHECK_INT_EQ(add("user/is_ok.glsl",
                     "#pragma halo module is_ok\n"
                     "#pragma halo hook sample\n"
                     "#pragma halo param label float default=-1 min=-1 max=100\n"
                     "#pragma halo is keeps_empty\n"
                     "#pragma halo is labels_when=label\n"
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_OK);
    return 0;
}

/* Every error in a file is reported, each at its own line. */
static int test_all_errors_reported(void)
{
    CHECK_INT_EQ(add("user/many.glsl",
                     "#pragma halo module many_errors\n"                  /* 1 */
                     "#pragma halo hook sample\n"                         /* 2 */
                     "#pragma halo frobnicate\n"                          /* 3 */
                     "#pragma halo param a float default=1\n"             /* 4 */
                     "#pragma halo param b floaty default=1\n"            /* 5 */
                     "#pragma halo param c float default=9 min=0 max=1\n" /* 6 */
                     "#pragma halo param a float default=1\n"             /* 7 */
                     "#pragma halo param\n"                               /* 8 */
                     "#pragma halo hook sample\n"                         /* 9 */
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_ERROR_INPUT);
    CHECK_DIAG_LINE(diags, HALO_MSG_ANNOTATION_UNKNOWN, 3);
    CHECK_DIAG_LINE(diags, HALO_MSG_PARAM_TYPE_UNKNOWN, 5);
    CHECK_DIAG_LINE(diags, HALO_MSG_PARAM_DEFAULT_INVALID, 6);
    CHECK_DIAG_LINE(diags, HALO_MSG_PARAM_DUPLICATE, 7);
    CHECK_DIAG_LINE(diags, HALO_MSG_ANNOTATION_SYNTAX, 8);
    CHECK_DIAG_LINE(diags, HALO_MSG_ANNOTATION_DUPLICATE, 9);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 6);
    for (size_t i = 0; i < halo_diagnostics_describe(diags).count; i++) {
        const halo_diagnostic *g = halo_diagnostics_get(diags, i);
        CHECK_STR_EQ(g->file, "user/many.glsl");
        CHECK(g->column >= 1);
        CHECK(g->source_line != NULL);
    }
    CHECK(halo_library_find(library, "many_errors") == NULL);
    return 0;
}

/* Columns point at the offending word. */
/* Adds a module that must be refused: the column of its `id` error at `line`, -1 when
 * it was taken or has no such error. */
static int refused_at(const char *source, halo_message_id id, int line)
{
    if (add("user/refused.glsl", source) != HALO_ERROR_INPUT)
        return -1;
    const halo_diagnostic *g = check_find_diag(diags, id, line);
    return g ? g->column : -1;
}

static int test_columns(void)
{
    CHECK_INT_EQ(refused_at("#pragma halo module columns\n"
                            "#pragma halo hook sample\n"
                            "#pragma halo param k vec5 default=1\n"
                            "void apply(inout halo_sample s) {}\n",
                            HALO_MSG_PARAM_TYPE_UNKNOWN, 3),
                 22); /* "vec5" */
    return 0;
}

/* reach= of a pass: K, or [M*]B^(PARAM-i)[+K] with PARAM an int parameter and B 2 or 4;
 * when= a list [!]PARAM,... of bool parameters; anything else at the word. */
static int test_pass_reach_syntax(void)
{
    static const struct {
        const char *word;
        halo_message_id id;
    } bad[] = {{"reach=x", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=2^(n-j)", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=2^(n-i)+", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=-1", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=2^(n-i)*2", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=5000", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=3^(n-i)", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=3*4", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=0*4^(n-i)", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=*4^(n-i)", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=5000*2^(n-i)", HALO_MSG_ANNOTATION_SYNTAX},
               {"reach=3*4^(n-i)+", HALO_MSG_ANNOTATION_SYNTAX},
               {"when=on,", HALO_MSG_ANNOTATION_SYNTAX},
               {"when=,on", HALO_MSG_ANNOTATION_SYNTAX},
               {"when=on,,on", HALO_MSG_ANNOTATION_SYNTAX},
               {"when=on,!", HALO_MSG_ANNOTATION_SYNTAX},
               {"when=On", HALO_MSG_ANNOTATION_SYNTAX},
               {"when=on,nope", HALO_MSG_PASS_INVALID},
               {"when=!on,n", HALO_MSG_PASS_INVALID},
               {"reach=2^(nope-i)", HALO_MSG_PASS_INVALID},
               {"reach=2^(on-i)", HALO_MSG_PASS_INVALID},
               {"reach=3*4^(on-i)+1", HALO_MSG_PASS_INVALID},
               {"running=max", HALO_MSG_ANNOTATION_SYNTAX},
               /* running=: inputs=IMAGE,OUTPUT (below) */
               {"reach=0 running=associative", HALO_MSG_PASS_INVALID}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char source[512];
        snprintf(source, sizeof source,
                 "#pragma halo module reach_syntax\n"
                 "#pragma halo hook image\n"
                 "#pragma halo param n int default=2 min=1 max=4\n"
                 "#pragma halo param on bool default=true\n"
                 "#pragma halo image a\n"
                 "#pragma halo pass p entry=f inputs=a output=a %s\n"
                 "halo_channels f(ivec2 pixel) { return halo_input(0, pixel); }\n",
                 bad[i].word);
        int column = refused_at(source, bad[i].id, 6);
        if (column != (bad[i].id == HALO_MSG_ANNOTATION_SYNTAX ? 47 : 1))
            CHECK_FAIL_AT("%s: no error at line 6 (column %d)", bad[i].word, column);
        CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 1);
    }
    CHECK_INT_EQ(add("user/reach.glsl",
                     "#pragma halo module reach_ok\n"
                     "#pragma halo hook image\n"
                     "#pragma halo param n int default=2 min=1 max=4\n"
                     "#pragma halo param on bool default=true\n"
                     "#pragma halo image a\n"
                     "#pragma halo pass p entry=f inputs=a output=a reach=2^(n-i)+1\n"
                     "#pragma halo pass q entry=f inputs=a output=a reach=0\n"
                     "#pragma halo image b\n"
                     "#pragma halo pass m entry=f inputs=a,b output=b reach=0 running=associative\n"
                     "#pragma halo pass r entry=f inputs=a output=a reach=3*4^(n-i)+1 when=on\n"
                     "#pragma halo pass s entry=f inputs=a output=a reach=4^(n-i) "
                     "when=!on,halo_full_size\n"
                     "halo_channels f(ivec2 pixel) { return halo_input(0, pixel); }\n"),
                 HALO_OK);
    return 0;
}

/* running=associative: a pass inputs=IMAGE,OUTPUT with reach=0 at the generation, one a
 * generation; anything else at the pass's line. */
static int test_pass_running(void)
{
    static const char *const bad[] = {"inputs=b,a output=b reach=0",          "inputs=a,b output=b",
                                      "inputs=a,b output=b reach=1",          "inputs=a,b output=b reach=2^(n-i)",
                                      "inputs=a,b output=b reach=0 repeat=n", "inputs=a,b output=b reach=0 first=a",
                                      "inputs=a,b output=b reach=0 start=2",  "inputs=a,b output=b reach=0 at=post",
                                      "inputs=a,a output=a reach=0",          "inputs=a,b,b output=b reach=0"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char source[512];
        snprintf(source, sizeof source,
                 "#pragma halo module running\n"
                 "#pragma halo hook image\n"
                 "#pragma halo param n int default=2 min=1 max=4\n"
                 "#pragma halo image a\n"
                 "#pragma halo image b\n"
                 "#pragma halo pass p entry=f %s running=associative\n"
                 "halo_channels f(ivec2 pixel) { return halo_input(0, pixel); }\n",
                 bad[i]);
        if (refused_at(source, HALO_MSG_PASS_INVALID, 6) != 1)
            CHECK_FAIL_AT("%s running=associative: no PASS_INVALID at line 6", bad[i]);
    }
    return 0;
}

/* A parameter named after a GLSL keyword, type or reserved word is refused at its
 * annotation (the module's code could not use it), not later in the shader. */
static int test_reserved_param_names(void)
{
    static const char *const names[] = {"float",  "sample", "vec3", "dvec2", "mat2x3",
                                        "output", "filter", "gl_x", "a__b"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char source[512];
        snprintf(source, sizeof source,
                 "#pragma halo module reserved_param\n"
                 "#pragma halo hook sample\n"
                 "#pragma halo param %s float default=1\n"
                 "void apply(inout halo_sample s) {}\n",
                 names[i]);
        if (refused_at(source, HALO_MSG_ANNOTATION_SYNTAX, 3) != 20)
            CHECK_FAIL_AT("no ANNOTATION_SYNTAX at line 3, column 20 for the parameter name '%s'", names[i]);
        CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 1);
    }
    /* a built-in function's name is no keyword: the linker renames parameters */
    CHECK_INT_EQ(add("user/reserved.glsl",
                     "#pragma halo module builtin_name\n"
                     "#pragma halo hook sample\n"
                     "#pragma halo param texture float default=1\n"
                     "void apply(inout halo_sample s) { s.opacity *= texture; }\n"),
                 HALO_OK);
    return 0;
}

/* The real reason, at its place: 25 words are too many (at the 25th), not "unclosed
 * quote?" at the directive; an unclosed quote at the quote. */
static int test_annotation_words(void)
{
    CHECK_INT_EQ(refused_at("#pragma halo module many_words\n"
                            "#pragma halo hook sample\n"
                            "#pragma halo needs a b c d e f g h i j k l m n o p q r s t u v w x y\n"
                            "void apply(inout halo_sample s) {}\n",
                            HALO_MSG_ANNOTATION_SYNTAX, 3),
                 66); /* "y", the 25th word */
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 1);
    CHECK_INT_EQ(refused_at("#pragma halo module unclosed\n"
                            "#pragma halo hook sample\n"
                            "#pragma halo summary \"no end\n"
                            "void apply(inout halo_sample s) {}\n",
                            HALO_MSG_ANNOTATION_SYNTAX, 3),
                 22); /* the quote */
    return 0;
}

/* Comments after an annotation are no part of it (the preprocessor drops them), and a
 * malformed 'module' or 'hook' annotation is one error, not also "no module". */
static int test_annotation_comments(void)
{
    CHECK_INT_EQ(add("user/comments.glsl",
                     "#pragma halo module commented // the module\n"
                     "#pragma halo hook sample /* per sample */\n"
                     "#pragma halo summary \"a // in quotes stays\" // a comment\n"
                     "#pragma halo param k float default=1 \"k\" // its meaning\n"
                     "void apply(inout halo_sample s) { s.opacity *= k; }\n"),
                 HALO_OK);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).count, 0);
    const halo_module *m = halo_library_find(library, "commented");
    CHECK(m != NULL);
    CHECK(!strcmp(halo_module_describe(m).summary, "a // in quotes stays"));
    CHECK_INT_EQ(add("user/comments.glsl",
                     "#pragma halo module Bad-Name\n"
                     "#pragma halo hook sample\n"
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 1);
    CHECK_INT_EQ(add("user/comments.glsl",
                     "#pragma halo module bad_hook\n"
                     "#pragma halo hook sample per sample\n"
                     "void apply(inout halo_sample s) {}\n"),
                 HALO_ERROR_INPUT);
    CHECK_INT_EQ(halo_diagnostics_describe(diags).errors, 1);
    return 0;
}

static int test_add_file(void)
{
    halo_diagnostics_clear(diags);
    CHECK_INT_EQ(halo_library_add(library, "/nonexistent/dir/module.glsl", NULL, HALO_ADD_NEW, diags), HALO_ERROR_IO);
    CHECK_DIAG(diags, HALO_MSG_IO_READ);
    return 0;
}

int main(void)
{
    library = check_library_setup(&diags);
    if (halo_diagnostics_describe(diags).count) {
        check_print_diags(diags);
        SETUP_FAIL("the embedded modules gave diagnostics");
    }
    RUN_TEST(test_valid_module);
    RUN_TEST(test_builtin_modules);
    RUN_TEST(test_unknown_directive);
    RUN_TEST(test_malformed_param);
    RUN_TEST(test_unknown_type);
    RUN_TEST(test_default_invalid);
    RUN_TEST(test_duplicate_param);
    RUN_TEST(test_missing_annotations);
    RUN_TEST(test_entry_missing);
    RUN_TEST(test_duplicate_module);
    RUN_TEST(test_reserved_name);
    RUN_TEST(test_all_errors_reported);
    RUN_TEST(test_is_annotation);
    RUN_TEST(test_columns);
    RUN_TEST(test_reserved_param_names);
    RUN_TEST(test_pass_reach_syntax);
    RUN_TEST(test_pass_running);
    RUN_TEST(test_annotation_words);
    RUN_TEST(test_annotation_comments);
    RUN_TEST(test_add_file);
    halo_library_destroy(library);
    halo_diagnostics_destroy(diags);
    return check_exit_status();
}
