"""``python -m glidectl ...``: the same command line as the ``glidectl`` script (:func:`glidectl.cli.main`)."""

from .cli import main

raise SystemExit(main())
