"""Golden-curve regression: the comparison rule (compare.py) used by regression/run (docs/regression.md)."""
