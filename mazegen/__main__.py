"""``python -m mazegen``: the same as the ``mazegen`` command."""

from mazegen.cli.main import main

if __name__ == "__main__":  # worker processes import this module again: they must not start a command
    main()
