"""``python -m mazegen``: the same as the ``mazegen`` command."""

from mazegen.cli.main import main

main()
