/* The measurements of docs/feature-halos.md: for the built-in volume and the MRI head,
 * the share of voxels above gradient thresholds (Svakhine & Ebert 2003, Table 2), the
 * GPU halo-buffer build time against that share, and the error of the low-gradient
 * cutoff and of the half-resolution buffer against the exact reference. */
#ifndef HALO_FEATURE_REPORT_H
#define HALO_FEATURE_REPORT_H

/* argv: [--size N] [--mri PATH] [--mri-size N] [--splat N] [--repeat N]. Prints the
 * tables to stdout (Markdown). Creates a headless context unless one is current.
 * Returns 0, 1 on a failed measurement, 2 on bad arguments. */
int halo_feature_report_main(int argc, char **argv);

#endif
