/* halo-validate blur: the outline passes' Gaussian blur (direct, separable,
 * linear-sampled; GPU and CPU) against direct 2D convolution, with timings beside the
 * paper's anchors (docs/blur.md). */
#ifndef HALO_BLUR_REPORT_H
#define HALO_BLUR_REPORT_H

/* argv[0] is the subcommand ("blur"); [--size N] [--repeat R] [--kernels K,...] [--help].
 * Returns 0, 1 when an error exceeds 1e-5, 2 on usage or setup failure. */
int halo_blur_report_main(int argc, char **argv);

#endif
