# The manual: the docs/ folder ships whole in the tarball (every page and picture, so
# that a new page cannot be left out).
EXTRA_DIST += docs
