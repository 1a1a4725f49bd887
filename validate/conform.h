/* halo-validate conform: renders every per-sample stage through OSMesa and compares it
 * with the C emulation (docs/accuracy.md). */
#ifndef HALO_CONFORM_H
#define HALO_CONFORM_H

/* argv[0] is the subcommand ("conform"); handles [--stage NAME] [--size N] [-v] [--help].
 * Prints one row per test; returns 0 when all pass, 1 on any FAIL, 2 on a usage or
 * setup failure (no OpenGL context, no library). */
int halo_conform_main(int argc, char **argv);

#endif
