"""Rules and findings: what every check, run and simulation reports, and how.

* :mod:`~skillwright.rules.finding` — :class:`Finding`: code, group, severity, place,
  message, data and fix (with its safety).
* :mod:`~skillwright.rules.registry` — :class:`Rule` and the registry of all rules (codes
  SW101..SW799), their documentation, and the selectors ``--select``/``--ignore`` take.
* :mod:`~skillwright.rules.fixes` — applying fixes: safe ones, or unsafe ones too when asked.
* :mod:`~skillwright.rules.settings` — a project's selection of rules (``[tool.skillwright]``).
"""
