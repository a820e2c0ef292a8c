"""The exceptions brdfbake raises: brdfbake.Error and a subclass per kind of error."""

from __future__ import annotations

from typing import Any, Optional


class Error(Exception):
    """An error the brdfbake library reports.

    The message names what is wrong and where: the file and line, or the JSON path of a spec
    (``spec: maps[0].material.exponent: must be > 0, got -3``), or the keyword argument.
    ``kind`` says which kind of error it is (the subclass says the same):

    ========================  ==================  =============================================
    subclass                  kind                the tool's exit status and meaning
    ========================  ==================  =============================================
    InvalidArgumentError      invalid_argument    2: a value outside its documented range
    InvalidInputError         invalid_input       2: a malformed file or spec
    IoError                   io                  3: a file could not be read or written
    ResourceError             resource            4: more memory than the budget allows
    NumericalError            numerical           1: no finite result
    ========================  ==================  =============================================

    ``result`` is what was done before the error where there is something: bake() raises the first
    failed map's error with the BakeResult of every map (the others were written).
    """

    kind: str = "error"

    def __init__(self, message: str, *, result: Optional[Any] = None) -> None:
        super().__init__(message)
        self.message = message
        self.result = result


class InvalidArgumentError(Error, ValueError):
    """A value outside its documented range (a keyword argument, an option)."""

    kind = "invalid_argument"


class InvalidInputError(Error, ValueError):
    """A malformed file or spec; the message names the file, line or JSON path."""

    kind = "invalid_input"


class IoError(Error, OSError):
    """A file could not be read or written; the message names it."""

    kind = "io"


class ResourceError(Error, MemoryError):
    """The work would need more memory than allowed (BRDFBAKE_MEMORY_LIMIT, allow_large)."""

    kind = "resource"


class NumericalError(Error, ArithmeticError):
    """A computation could not produce a finite result."""

    kind = "numerical"


_BY_KIND = {cls.kind: cls for cls in (InvalidArgumentError, InvalidInputError, IoError, ResourceError, NumericalError)}


def error_class(kind: str) -> type[Error]:
    """The subclass of Error for a kind name ("invalid_input", ...); Error for an unknown one."""
    return _BY_KIND.get(kind, Error)
