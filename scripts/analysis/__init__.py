"""Trend analysis of the paper's parameter sweeps (scripts/trends; docs/trends.md).

Modules:
- inputs: reading a sweep folder (summary.csv, runs/<run>/ files)
- fits:   least-squares fits, group statistics, ratio of means with its uncertainty
- trends: the check definitions (one table, per tier) and their evaluation
- plots:  figures mirroring the paper's, saved in OUT/figures/
- output: JSONL check lines, trends.json, trends.md, the terminal table
- cli:    the command line of scripts/trends
- headline: the paper's headline trends as a stored record (validation/results/) and
          the report's first section
- paper_repro, paper_figures, paper_repro_cli: the paper, figure by figure, from the
          campaign's stored runs (scripts/paper-repro, the report's section;
          docs/paper-reproduction.md)
- run_plot: the command line of scripts/plot-run (two figures and a summary of one run folder)
- run_figures: the results and solver-diagnostics figures of one run folder
- sweep_plot: P_max and W_rms of sweep folders against the swept parameter (scripts/plot-sweep)

The run folder itself (timeseries, cycles, run.json, thermal phases) is read by the
package's ratchet.run_folder (reference_engine/python/ratchet), found through common.paths.

Run with Debian's interpreter, /usr/bin/python3.
"""
