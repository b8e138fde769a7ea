# SPDX-License-Identifier: MIT
# Libraries of fuzz targets beyond the default sta_io (one line per target).
set(STA_FUZZ_LIBS_strata sta_format)
