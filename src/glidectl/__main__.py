"""``python -m glidectl ...``: the same command line as the ``glidectl`` script (:func:`glidectl.cli.main`)."""

from .cli import main

__all__: list[str] = []

if __name__ == "__main__":
    raise SystemExit(main())
