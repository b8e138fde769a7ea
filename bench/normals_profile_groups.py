#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Sums a perf profile of strata-convert --normals into the groups of BENCHMARKS.md's
# fifteenth round (normals' decisions and fits, vertex boxes, cells, finishing, halo
# pass, byte planes, zstd, kernel, shared with a plain run), in samples, per cent and
# seconds at the sampling rate.
#
#   perf record -F RATE -g strata-convert IN.las --normals -o OUT.strata --force
#   perf report --no-children --stdio -n --sort dso,symbol | grep -E '^ +[0-9.]+%' |
#       awk '{ print $1, $2, $3, $5 }' > run.sym
#   python3 bench/normals_profile_groups.py run.sym RATE
import re
import sys

GROUPS = [
    ("normals: decisions and fits",
     r"^(decide_level.*|sta_eigen3_sym_d|sta_cholesky.*|sta_quadric_.*|sta_sphere_fit|"
     r"sta_sphere_normal|sta_normal_fit_moments|__cos_fma|__ieee754_atan2_fma|__sin_fma|"
     r"normalise_d|sta_normal_too_narrow_at|__fmin|fit_level.*|__atan2_fma)$"),
    ("normals: vertex boxes",
     r"^(vertex_at|vertex_cells|sta_cell_blocks_vertex_lower|nearest_box|"
     r"sta_higher_sums_add_moved|level_init|box_sphere|"
     r"sta_key_slots_double)$"),
    ("normals: finishing each point",
     r"^(finish_level|sta_octahedral_encode|sta_trajectory_at_memo|sta_trajectory_at|"
     r"sta_normal_orient_at|sta_normal_store_at|sta_splat_pack|sta_normal_halo_reach)$"),
    ("normals: cells",
     r"^(sta_cell_order|sta_cell_blocks_.*|"
     r"add_cell|sta_cell_moments_.*|sta_normal_gather_positions|sta_normals_compute|"
     r"cell_at|grow_cells|grow_blocks)$"),
    ("halo pass and trajectory", r"^(halo_worker|sta_trajectory_add|sta_halo_.*|flush)$"),
    ("byte planes", r"^(sta_byte_planes_split|sta_byte_planes_join)$"),
    ("shared with plain",
     r"^(las_read_positions|build|hand_over|encode_column|sta_record_.*|count_batch|locate|"
     r"decode_format_7|sta_index_chunk|distribute_batch.*|pack\.constprop.*|"
     r"sta_distribute_plan|reserve|emit|sta_strata_.*|index_worker)$"),
]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__ or "usage: normals_profile_groups.py RUN.sym RATE")
    totals, total = {}, 0
    with open(sys.argv[1]) as f:
        for line in f:
            fields = line.split()
            if len(fields) < 4:
                continue
            samples, dso, symbol = int(fields[1]), fields[2], fields[3]
            total += samples
            if "zstd" in dso:
                group = "zstd"
            elif "kernel" in dso:
                group = "kernel"
            else:
                group = next((g for g, rx in GROUPS if re.match(rx, symbol)), "other")
            totals[group] = totals.get(group, 0) + samples
    rate = float(sys.argv[2])
    for group, samples in sorted(totals.items(), key=lambda t: -t[1]):
        print(f"| {group} | {samples} | {100 * samples / total:.1f} % | {samples / rate:.2f} |")
    print(f"| total | {total} | 100 % | {total / rate:.2f} |")


if __name__ == "__main__":
    main()
