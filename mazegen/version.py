"""MazeGen's version, in a module of its own: the runtime and the generator stamp it on what they
write without importing the package's API (which would tie them to the language)."""

__version__ = "0.1.0"
