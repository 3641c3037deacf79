"""How a check's status at the paper tier is shown, in the tables of
docs/paper-reproduction.md and in the titles of its figures (one wording for both)."""

from __future__ import annotations

import math

#: Display text and CSS class of a check's status at the paper tier.
RESULT_TEXT = {"passed": "PASS", "unresolved": "NOT RESOLVED", "contradicted": "CONTRADICTED",
               "skipped": "SKIP"}
RESULT_CLASS = {"PASS": "pass", "NOT RESOLVED": "unresolved", "CONTRADICTED": "contradicted",
                "FAIL": "fail", "SKIP": "skip"}


def result_text(status: str, measured) -> str:
    """A check's result as shown: at the paper tier a resolved opposite is written
    "failed" (docs/trends.md, States); it is shown as what it is, CONTRADICTED (at the
    paper's own scale), never as a pass. A value that is not a number is a FAIL."""
    if status == "failed":
        finite = measured is not None and math.isfinite(measured)
        return "CONTRADICTED" if finite else "FAIL"
    return RESULT_TEXT[status]
