/* Two threads at once (halo.h, "Threads"): each sets libhalo up with its own logger
 * and shuts it down again, many times, while the other validates; both read scenes from
 * one shared library and link them. Each logger must receive exactly its own thread's
 * diagnostics, and no shutdown may finalize glslang under the other thread's compile.
 * .ci/run also runs this test under ThreadSanitizer (configure --enable-tsan), which
 * reports any data race in libhalo's setup, logger or reference counts. */
#include "check.h"

#include <pthread.h>
#include <stdatomic.h>

#define ROUNDS 10

typedef struct worker {
    pthread_t thread; /* set by the thread itself */
    const halo_library *library;
    size_t diagnostics; /* diagnostics this thread's calls produced */
    size_t logged;      /* those its logger received */
    atomic_int foreign; /* logger calls made on another thread */
    int failed;
} worker;

static void logger(const halo_diagnostic *g, void *user_data)
{
    worker *w = user_data;
    (void)g;
    if (!pthread_equal(pthread_self(), w->thread)) {
        atomic_fetch_add(&w->foreign, 1);
        return;
    }
    w->logged++;
}

static const char bad_shader[] = "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(undeclared_name); }\n";

static int work(worker *w)
{
    for (int round = 0; round < ROUNDS; round++) {
        CHECK_INT_EQ(halo_setup(&(halo_setup_desc){.logger = logger, .user_data = w}), HALO_OK);
        halo_diagnostics *d = halo_diagnostics_create();
        CHECK(d != NULL);
        CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.source = bad_shader,
                                                         .file = "bad.frag",
                                                         .kind = HALO_SHADER_FRAGMENT,
                                                         .target = HALO_TARGET_GLSL330},
                                   d),
                     HALO_ERROR_INPUT);
        CHECK_DIAG_LINE(d, HALO_MSG_GLSL_ERROR, 3); /* the other thread's log never mixes in */
        CHECK(halo_scene_load("bad.json", "{\"stages\": [\"no_such_stage\"]}", w->library, d) == NULL);
        CHECK_DIAG(d, HALO_MSG_SCENE_STAGE_UNKNOWN);
        halo_scene *scene = halo_scene_load(
            "good.json", "{\"halo_scene\": 1, \"stages\": [\"boundary\", \"silhouette\"]}", w->library, d);
        CHECK(scene != NULL);
        halo_program *p =
            halo_link(&(halo_link_desc){.library = w->library, .scene = scene, .host_source = check_sample_host}, d);
        CHECK(p != NULL);
        CHECK_INT_EQ(halo_validate(&(halo_validate_desc){.program = p}, d), HALO_OK);
        halo_program_destroy(p);
        halo_scene_destroy(scene);
        w->diagnostics += halo_diagnostics_describe(d).count + halo_diagnostics_describe(d).dropped;
        halo_diagnostics_destroy(d);
        halo_shutdown();
    }
    return 0;
}

static void *run(void *arg)
{
    worker *w = arg;
    w->thread = pthread_self();
    w->failed = work(w);
    return NULL;
}

static int test_two_threads(void)
{
    halo_diagnostics *d;
    halo_library *lib = check_library_setup(&d);
    worker workers[2] = {{.library = lib}, {.library = lib}};
    pthread_t handles[2];
    for (int i = 0; i < 2; i++)
        SETUP(pthread_create(&handles[i], NULL, run, &workers[i]) == 0);
    for (int i = 0; i < 2; i++)
        SETUP(pthread_join(handles[i], NULL) == 0);
    for (int i = 0; i < 2; i++) {
        CHECK_INT_EQ(workers[i].failed, 0);
        CHECK_INT_EQ(atomic_load(&workers[i].foreign), 0);
        CHECK_INT_EQ(workers[i].logged, workers[i].diagnostics);
    }
    halo_library_destroy(lib);
    halo_diagnostics_destroy(d);
    return 0;
}

int main(void)
{
    RUN_TEST(test_two_threads);
    return check_exit_status();
}
