bin_PROGRAMS += validate/halo-validate
validate_halo_validate_SOURCES = validate/halo-validate.c validate/conform.c validate/conform.h
nodist_EXTRA_validate_halo_validate_SOURCES = build-aux/force-cxx-link.cc
validate_halo_validate_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/examples
validate_halo_validate_LDADD = $(HALO_TOOL_LIBS)
dist_man_MANS += validate/halo-validate.1
