"""Helpers shared by the Python scripts of ratchet (one implementation each).

Modules:
  fsutil    atomic file writing: write_atomic (the package's), write_csv_atomic, save_figure_atomic (format from the extension)
  jsonc     JSON with // and /* */ comments, as the engine's scene parser reads it
  jsonsafe  JSON-ready copies of numpy/pandas values (NaN and infinities to null)
  figures   the report's figure folder: OUT/figures/<name>.png with a caption <name>.txt
  paths     the repository root and the engine binary ($RATCHET_BIN), from the package ratchet
  gitinfo   the commit of the checkout and whether it has uncommitted changes

Importing: the folder scripts/ must be on sys.path, then `from common.fsutil import
write_atomic`. The entry points put it there: scripts/trends, scripts/compare-methods
and scripts/report.py insert their own folder; regression/run,
regression/make_compare_vectors.py and validation/liggghts/check.py insert
<repository>/scripts; the tests in scripts/tests insert their parent folder.
jsonc and gitinfo need only the standard library; paths and fsutil import this checkout's
package ratchet (reference_engine/python/ratchet: numpy and pandas), jsonsafe numpy and
pandas, figures matplotlib's savefig through the figure it is given.

Run with Debian's interpreter, /usr/bin/python3.
"""
