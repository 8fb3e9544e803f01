"""The study's report: runs.csv / runs.json, plots, tables and findings in report.md and report.html.

Everything stated in the findings is computed from the measured records; a finding that does not reproduce is
reported as such.  Modules, in the order the data flows: results (the stored runs, grouped into curves),
curves (measures of one curve: slope, cost per sample, time to an error), findings (the paper's claims) and
equal_error (target error, Cycles) as numbers, wording (every number formatted, once), plots, document
(Markdown + HTML), compose (write_report: the sections in order).
"""
from .compose import write_report  # noqa: F401
