"""The Jinja2 templates of the reports (scripts/templates/): one environment for every
script that renders them (scripts/report.py, scripts/paper-repro), so that a template
included by both sees the same filters and the same strictness."""

from __future__ import annotations

import os
from pathlib import Path

import jinja2

#: scripts/templates: report.md.j2, report.html.j2 and what they include.
TEMPLATES_DIR = Path(__file__).resolve().parent.parent / "templates"


def md_cell(text) -> str:
    """One Markdown table cell: white space folded, backslashes and pipes escaped, an
    empty cell a space (the templates' md_cell filter)."""
    return " ".join(str(text).split()).replace("\\", "\\\\").replace("|", "\\|") or " "


def environment(folder: str | os.PathLike | None = None) -> jinja2.Environment:
    """HTML templates (*.html.j2) autoescaped, the Markdown ones not; an undefined
    variable is an error (a template must not show a blank where a value is missing);
    filter md_cell."""
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(folder if folder is not None else TEMPLATES_DIR)),
        autoescape=jinja2.select_autoescape(["html", "html.j2"]),
        undefined=jinja2.StrictUndefined, keep_trailing_newline=True, trim_blocks=True,
        lstrip_blocks=True)
    env.filters["md_cell"] = md_cell
    return env


def render(name: str, context: dict, folder: str | os.PathLike | None = None) -> str:
    """One template with the context. Raises jinja2.TemplateNotFound (an OSError) for a
    missing template, jinja2.UndefinedError for a missing variable."""
    return environment(folder).get_template(name).render(context)
