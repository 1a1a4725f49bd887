#include "diag.h"
#include "internal.h"

#include <glslang/Include/glslang_c_interface.h>
#include <pthread.h>

/* glslang's process state lives while this count is above zero: one for each
 * halo_setup not yet paired with halo_shutdown, one for each validation in flight
 * (halo_glslang_acquire), so that one thread's last halo_shutdown never finalizes
 * glslang under another thread's compile. The lock also orders glslang's initialize
 * and finalize against each other. */
static pthread_mutex_t setup_lock = PTHREAD_MUTEX_INITIALIZER;
static long setup_count;

/* Takes one reference; initializes glslang on the first. With only_if_set, takes it
 * only when glslang is already initialized. Returns 1 when taken. */
static int setup_take(int only_if_set)
{
    pthread_mutex_lock(&setup_lock);
    int ok = setup_count > 0 || (!only_if_set && glslang_initialize_process());
    if (ok)
        setup_count++;
    pthread_mutex_unlock(&setup_lock);
    return ok;
}

/* Drops one reference; finalizes glslang with the last. Returns 0 when none was held. */
static int setup_drop(void)
{
    pthread_mutex_lock(&setup_lock);
    int held = setup_count > 0;
    if (held && --setup_count == 0)
        glslang_finalize_process();
    pthread_mutex_unlock(&setup_lock);
    return held;
}

halo_status halo_setup(const halo_setup_desc *desc)
{
    if (!setup_take(0))
        return HALO_ERROR_IO;
    halo_diag_thread_setup(desc);
    return HALO_OK;
}

void halo_shutdown(void)
{
    if (setup_drop())
        halo_diag_thread_shutdown();
}

int halo_glslang_acquire(halo_diagnostics *diag, const char *function)
{
    if (setup_take(1))
        return 1;
    halo_diag_error(diag, USAGE, "", 0, 0, "%s: call halo_setup first: the GLSL compiler is not initialized", function);
    return 0;
}

halo_status halo_glslang_release_with(halo_status st)
{
    setup_drop();
    return st;
}
