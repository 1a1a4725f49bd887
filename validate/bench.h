/* halo-validate bench: the frame rate of volumetric halos against the same renderer
 * without them, as Table 1 of Bruckner & Groller 2007 (docs/volumetric-halos-performance.md). */
#ifndef HALO_BENCH_H
#define HALO_BENCH_H

/* argv[0] is the subcommand ("bench"); handles [--size N] [--volume-size N] [--repeat R]
 * [--table1] [--help]. Prints the table on stdout, progress on stderr. Returns 0, or 2
 * on a usage or setup failure. */
int halo_bench_main(int argc, char **argv);

#endif
