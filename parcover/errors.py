"""Exceptions for user mistakes: bad instance data, bad files, bad questions.

The command line turns every :class:`InputError` into one line on stderr and exit
status 2 (docs/format.md section 3); anything else is a bug and keeps its traceback.
"""

__all__ = ["InputError"]


class InputError(ValueError):
    """A user mistake. The message is one sentence naming the problem."""
