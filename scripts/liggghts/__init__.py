"""Cross-method verification of the ratchet NSCD engine against soft-sphere DEM
(LIGGGHTS 3.8.0). Modules:

  scene       reads a sphere scene's settings; its spheres from the engine (`ratchet bodies`)
  units       dimensionless engine units <-> SI units of the DEM run
  translate   scene -> LIGGGHTS input deck + STL wall meshes + meta.json
  parse       LIGGGHTS log -> CSV with the engine's timeseries.csv columns
  compare     runs both methods, per-cycle peak pressures, plots (scripts/compare-methods)

See docs/liggghts.md.
"""
