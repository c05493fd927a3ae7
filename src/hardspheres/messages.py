"""One-line messages: how user input and failed files are echoed.

Pure Python (no numpy), so that the assignment's program can use it.
Everything that echoes what a user typed or named goes through
:func:`quote`, so a 10 MB token or a name holding NUL or ESC bytes prints
as a short, harmless line; every OSError shown to a user goes through
:func:`oserror_line`, which names the file.
"""

#: Longest piece of user input echoed in a message [characters].
QUOTE_LIMIT = 40


def quote(text: object, limit: int = QUOTE_LIMIT) -> str:
    """``text`` quoted for a message: at most ``limit`` characters, control bytes escaped.

    Example:
        >>> quote("abc")
        "'abc'"
        >>> quote("a\\x1b[2Jb")
        "'a\\\\x1b[2Jb'"
        >>> quote("9" * 100)
        "'9999999999999999999999999999999999999999'... (100 characters)"
    """
    text = str(text)
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}... ({len(text)} characters)"


def oserror_line(err: OSError, path: object = None) -> str:
    """One line for an :class:`OSError`: the file it is about, then the reason.

    Args:
        err: the error.
        path: the file, if ``err`` does not name it (``err.filename``).

    Example:
        >>> import errno
        >>> oserror_line(OSError(errno.ENOSPC, "No space left on device"), "out.gsd")
        'out.gsd: No space left on device'
    """
    name = err.filename if path is None else path
    reason = err.strerror or str(err) or type(err).__name__
    if name is None:
        return reason.replace("\n", " ")
    name = str(name)
    shown = name if name.isprintable() and len(name) <= 200 else quote(name, 200)
    return f"{shown}: {reason}".replace("\n", " ")


def plus_minus(mean: float, error: float | None, fmt: str = ".4g", error_fmt: str = ".2g") -> str:
    """``"mean +- error"``, or the mean alone, saying so, when there is no error bar to show.

    An error of exactly 0, NaN or infinity is never printed as if it were an
    error bar (it means too few independent samples, not an exact value).

    Args:
        mean: the estimate.
        error: its standard error (``None``: none was computed).
        fmt, error_fmt: format specifications of the two.

    Example:
        >>> plus_minus(0.51234, 0.0123)
        '0.5123 +- 0.012'
        >>> plus_minus(0.5, 0.0)
        '0.5 (no error bar: too few independent samples)'
    """
    if error is None:
        return f"{mean:{fmt}}"
    if not (error > 0 and error != float("inf")):  # NaN fails the first test
        return f"{mean:{fmt}} (no error bar: too few independent samples)"
    return f"{mean:{fmt}} +- {error:{error_fmt}}"
