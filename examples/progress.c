/* Progress on stderr (progress.h). */
#include "progress.h"

#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double halo_progress_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void *progress_main(void *arg)
{
    halo_progress *p = arg;
    pthread_mutex_lock(&p->lock);
    double next = p->start + 1.0;
    while (!p->done) {
        struct timespec until;
        until.tv_sec = (time_t)next;
        until.tv_nsec = (long)((next - (double)until.tv_sec) * 1e9);
        pthread_cond_timedwait(&p->wake, &p->lock, &until); /* the condition uses CLOCK_MONOTONIC */
        if (p->done)
            break;
        double now = halo_progress_now();
        if (now >= next) {
            fprintf(stderr, p->tty ? "\r%s: %s: %.0f s" : "%s: %s: %.0f s\n", p->tool, p->what, now - p->start);
            fflush(stderr);
            p->printed = 1;
            next = now + (p->tty ? 1.0 : 5.0);
        }
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

void halo_progress_begin(halo_progress *p, const char *tool, const char *what, int timer)
{
    memset(p, 0, sizeof *p);
    p->tool = tool;
    p->start = halo_progress_now();
    p->next = p->start + 1.0;
    snprintf(p->what, sizeof p->what, "%s", what);
    if (!tool)
        return;
    p->tty = isatty(fileno(stderr));
    if (!timer)
        return;
    pthread_condattr_t attributes;
    pthread_condattr_init(&attributes);
    pthread_condattr_setclock(&attributes, CLOCK_MONOTONIC);
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, &attributes);
    pthread_condattr_destroy(&attributes);
    p->running = pthread_create(&p->thread, NULL, progress_main, p) == 0;
    if (!p->running) {
        pthread_cond_destroy(&p->wake);
        pthread_mutex_destroy(&p->lock);
    }
}

void halo_progress_count(int done, int total, void *progress)
{
    halo_progress *p = progress;
    double now = halo_progress_now();
    if (!p->tool || now < p->next || done >= total)
        return;
    /* llvmpipe queues draws: flushing keeps the count printed close to what has been
     * drawn. Only when printing: a flush after every slice cost 7 % of a frame, and
     * --quiet (no progress) must time the same frame (docs/halo-render.md). */
    if (p->gl)
        p->gl->Flush();
    fprintf(stderr, p->tty ? "\r%s: %s: %s %d of %d (%.0f s)" : "%s: %s: %s %d of %d (%.0f s)\n", p->tool, p->what,
            p->unit, done, total, now - p->start);
    fflush(stderr);
    p->printed = 1;
    p->next = now + (p->tty ? 0.25 : 5.0);
}

void halo_progress_end(halo_progress *p, int quiet, const char *done_text)
{
    double elapsed = halo_progress_now() - p->start;
    if (p->running) {
        pthread_mutex_lock(&p->lock);
        p->done = 1;
        pthread_cond_signal(&p->wake);
        pthread_mutex_unlock(&p->lock);
        pthread_join(p->thread, NULL);
        pthread_cond_destroy(&p->wake);
        pthread_mutex_destroy(&p->lock);
        p->running = 0;
    }
    if (p->tool && !quiet && elapsed > 1.0)
        fprintf(stderr, "%s%s: %s in %.1f s\n", p->printed && p->tty ? "\r\033[K" : "", p->tool, done_text, elapsed);
}
