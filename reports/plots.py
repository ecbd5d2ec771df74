#!/usr/bin/python3
"""PNG figures for an rtsim run, sweep or reproduce directory.

Usage:
    plots.py run DIR [--verbose]
    plots.py sweep DIR [--verbose]
    plots.py reproduce DIR [--verbose]
    plots.py animate DIR [--verbose]
    plots.py area DIR [--verbose]

run DIR reads DIR/report.json (and DIR/culled.npy when present) and writes:
  culled.png                where shadow rays were culled: one panel per light (fraction of pixels
                            culled per block, all on one colour scale; the % in its title is of all
                            pixels) and one "all lights" panel (culled lights per pixel). culled.npy
                            is uint16 (H, W), bit i = the primary hit's shadow ray to light i was
                            culled. Skipped when it is absent.
  plot_culling.png          the paper's Fig. 7: per light, % of non-empty leaves culled and % of
                            shadow rays culled. With culling off (config.run.lvb false, lvb null)
                            the figure is still written and only says so, so every run directory
                            gets the same plot_*.png files. Culling on but lvb null: the leaf bars
                            show n/a.
  plot_time_breakdown.png   busy / stalled / idle as % of the unit cycles per unit type (summed over
                            units).
  plot_cache_hit_rates.png  hit rate per unit type and cache level, and the DRAM row-hit rate.
  plot_energy.png           a priced run only (report.json's energy): each part's dynamic and static
                            energy, and each ray type's share with its energy per ray.
  plot_sample.png           a sampled run only (report.json's sampled: true): the primary phase's,
                            the shadow phase's and the frame's cycles, each estimate with its 95%
                            interval as an error bar, and each measured unit's cycles per phase by
                            its first ray (DIR/sample.csv, when present).
A sampled run's figures give the frame's estimate with its interval in their titles
("N ± H cycles ... (sampled, 95% interval)"); a full run's are as they were.

sweep DIR reads DIR/results.json (schema rtsim-sweep/1) and writes DIR/plots/<metric>_vs_<axis>.png
for every metric and every axis with at least 2 distinct values (the scene counts as an axis when
there are several); the sweep lists them in DIR/plots/index.md (reports/sweep_index.h). A metric
with an interval (cycles_total, cycles_primary, cycles_shadow, frame_ms_all, frame_ms_shadow) of
sampled rows (sampled: true, with the interval column <metric>_ci95) is drawn with its 95% interval
as error bars and "sampled, 95% interval" in the title.

reproduce DIR reads DIR/reproduction.json (schema rtsim-reproduction/1, written by
`rtsim reproduce`) and writes:
  reproduce_culling.png     per scene and light, % of shadow rays culled and % of leaves culled: the
                            paper's figures, ours with the paper's method, ours exact. Lights go by
                            index (the paper's lights are not ours, and their counts may differ).
                            The leaf denominators differ: the paper's are all leaves, ours the
                            non-empty leaves.
  reproduce_time.png        per scene, the frame-time reduction with culling ((off - on) / off) for
                            all rays and for the shadow rays, paper vs ours; the absolute times are
                            in the captions only.
A scene without the paper's figures, or without one of our runs, shows n/a in those places. Sampled
runs (reproduction.json's frame_ms_*_ci95 and reduction.*.ci95_pt) get error bars on our reductions
and their times' intervals in the captions.

area DIR reads the results.json of a sweep with the axes scene.lights.area_from_points.samples and
run.lvb (configs/sweeps/area-lights.yaml) and writes:
  plots/area_reduction.png         per scene and sample count, the frame-time reduction of culling
                                   on against off ((off - on) / off), one line per scene; with
                                   sampled rows, error bars from cycles_total_ci95 (the two runs'
                                   relative errors in quadrature, as if independent).
The sweep writes the tables, area_lights.md, itself (reports/area_report.cpp).

animate DIR reads DIR/frames.csv and DIR/host.csv (written by `rtsim animate`) and writes, over the
scene's time:
  plots/animate_cycles.png         cycles per frame with culling off and on.
  plots/animate_culled.png         % of shadow rays culled and % of (non-empty leaf, light) bits
                                   that are 0.
  plots/animate_preprocessing.png  host seconds of the kd-tree and the LVB per frame, and the LVB's
                                   work counts (kd-tree nodes visited, region tests, pair tests).
  frames.gif                       DIR/frames/frame_NNNN.png as an animated GIF (Pillow), at the
                                   scene's pace.
rtsim animate writes the tables, frames.csv, host.csv and summary.md, itself
(reports/animation_tables.h).

Every Markdown file comes from the rtsim command (C++); this script only draws figures.

Exit status 0 on success (silent unless --verbose, which lists the files written); on bad input one
line "plots.py: error: ..." on stderr and exit status 2. Needs only numpy and matplotlib.
"""

import argparse
import os
import sys

from rtsim_plots.animate_figures import animate
from rtsim_plots.area_figures import area
from rtsim_plots.common import InputError
from rtsim_plots.reproduce_figures import reproduce
from rtsim_plots.run_figures import run
from rtsim_plots.sweep_figures import sweep


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line and exit status 2, like every other input error
        raise InputError(message)


def main(argv=None):
    parser = _Parser(
        prog="plots.py", description="PNG figures for an rtsim run, sweep or reproduce directory."
    )
    parser.add_argument("--verbose", action="store_true", help="list the files written")
    sub = parser.add_subparsers(
        dest="mode", required=True, metavar="{run,sweep,reproduce,animate,area}"
    )
    for mode, text in (
        ("run", "figures for a run directory (report.json, culled.npy)"),
        ("sweep", "figures for a sweep directory (results.json)"),
        ("reproduce", "paper-vs-ours figures for an rtsim reproduce directory (reproduction.json)"),
        ("animate", "figures over time and frames.gif for an rtsim animate directory (frames.csv)"),
        ("area", "culling against samples per light for an area-light sweep (results.json)"),
    ):
        p = sub.add_parser(mode, help=text)
        p.add_argument("dir", metavar="DIR")
        p.add_argument(
            "--verbose",
            action="store_true",
            default=argparse.SUPPRESS,
            help="list the files written",
        )
    written = []
    try:
        args = parser.parse_args(argv)
        if not os.path.isdir(args.dir):
            raise InputError(f"{args.dir}: not a directory")
        {"run": run, "sweep": sweep, "reproduce": reproduce, "animate": animate, "area": area}[
            args.mode
        ](args.dir, written)
    except (InputError, OSError) as e:
        print("plots.py: error: " + " ".join(str(e).split()), file=sys.stderr)
        return 2
    if args.verbose:
        print("\n".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
