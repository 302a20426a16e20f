"""A run's results page, ``report.html``: one self-contained file (:mod:`.page`)."""

from agents.evaluation.report.page import write_report

__all__ = ["write_report"]
