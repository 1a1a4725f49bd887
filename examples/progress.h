/* Progress on stderr for steps that can take long (reading a volume, a frame): once a
 * second has passed, "TOOL: WHAT: N s" rewritten in place on a terminal (a line every
 * 5 s otherwise), and at the end "TOOL: DONE in N s" when the step took over a second.
 * A thread prints the time; a host that counts its draws prints "slice k of n" instead
 * (halo_progress_count). */
#ifndef HALO_PROGRESS_H
#define HALO_PROGRESS_H

#include "halo_gl_loader.h"

#include <pthread.h>

typedef struct halo_progress {
    const char *tool; /* NULL: quiet */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t thread;
    int running, done, printed, tty;
    double start, next;
    char what[160];
    /* halo_progress_count */
    const halo_glfuncs *gl;
    const char *unit;
} halo_progress;

double halo_progress_now(void);
/* Starts a step: timed by a thread when timer is 1, else counted (halo_progress_count). */
void halo_progress_begin(halo_progress *p, const char *tool, const char *what, int timer);
/* A host's count of what it has drawn (halo_slice_progress_fn's shape): "UNIT k of n".
 * Flushes gl before printing, so that the count is close to what has been drawn. */
void halo_progress_count(int done, int total, void *progress);
/* Ends the step; done_text is printed when it took more than a second (quiet: nothing). */
void halo_progress_end(halo_progress *p, int quiet, const char *done_text);

#endif
