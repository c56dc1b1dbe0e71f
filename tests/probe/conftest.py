"""The probe is run by ``python tests/probe/run.py``, never collected by pytest."""

collect_ignore_glob = ["*.py"]
