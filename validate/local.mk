bin_PROGRAMS += validate/halo-validate
validate_halo_validate_SOURCES = validate/halo-validate.c validate/conform.c validate/conform.h \
	validate/conform_slice.c validate/conform_slice.h validate/bench.c validate/bench.h validate/figure3.c \
	validate/bench_run.c validate/bench_run.h validate/bench_budget.c validate/bench_budget.h
nodist_EXTRA_validate_halo_validate_SOURCES = build-aux/force-cxx-link.cc
validate_halo_validate_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples
validate_halo_validate_LDADD = $(HALO_TOOL_LIBS)
validate_halo_validate_SOURCES += validate/conform_lines.c validate/conform_lines.h \
	validate/conform_feature.c validate/conform_feature.h
validate_halo_validate_SOURCES += validate/conform_outline.c validate/conform_outline.h validate/conform_internal.h \
	validate/blur_report.c validate/blur_report.h
dist_man_MANS += validate/halo-validate.1
