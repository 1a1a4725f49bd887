# validate/: halo-validate, the command-line front end of the library (check, link,
# list, conform, bench, blur). Conformance (halo-validate conform) is a registry of rows
# (conform_rows.c) run by family files (conform_<family>.c, figure3.c) over one harness
# (conform_harness.c: the run's context, statistics, printing, the probes, the command
# line); families depend on the harness only, conform.c walks the registry.
bin_PROGRAMS += validate/halo-validate
HALO_CONFORM_HARNESS = validate/conform_harness.c validate/conform_harness.h
validate_halo_validate_SOURCES = validate/halo-validate.c validate/conform.c validate/conform.h \
	validate/conform_rows.c validate/conform_rows.h $(HALO_CONFORM_HARNESS) \
	validate/conform_sample.c validate/conform_sample.h validate/conform_frame.c validate/conform_frame.h \
	validate/conform_render.c validate/conform_render.h validate/conform_passes.c validate/conform_passes.h \
	validate/figure3.c validate/figure3.h \
	validate/conform_slice.c validate/conform_slice.h validate/conform_segment.c validate/conform_segment.h \
	validate/bench.c validate/bench.h \
	validate/bench_run.c validate/bench_run.h validate/bench_budget.c validate/bench_budget.h \
	validate/bench_memory.c validate/bench_memory.h
nodist_EXTRA_validate_halo_validate_SOURCES = build-aux/force-cxx-link.cc
validate_halo_validate_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples
validate_halo_validate_LDADD = $(HALO_TOOL_LIBS)
validate_halo_validate_SOURCES += validate/conform_lines.c validate/conform_lines.h \
	validate/conform_feature.c validate/conform_feature.h
validate_halo_validate_SOURCES += validate/conform_outline.c validate/conform_outline.h \
	validate/blur_report.c validate/blur_report.h
dist_man_MANS += validate/halo-validate.1
