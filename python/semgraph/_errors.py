"""The exceptions of semgraph (raised by the C++ kernel, defined here so they are plain Python)."""

from typing import Optional, Tuple


class Error(Exception):
    """Base class of semgraph's errors."""


class RejectedError(Error):
    """A build-time operation (add, remove, handle lookup, set) was refused; nothing changed.

    code:        the stable snake_case error code, e.g. "multiple_pose_parents", "invalid_rotation"
    message:     what was refused and why, naming the frames, bodies and the conflicting relation
    discrepancy: for a repair whose consistency check refused the relation (add_pose/add_twist
                 with repair=), (position, angle): how far it is from the value the graph
                 derives (m and rad; m/s and rad/s for twists); None otherwise
    """

    def __init__(self, code: str, message: str,
                 discrepancy: Optional[Tuple[float, float]] = None) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.discrepancy = discrepancy

    def __str__(self) -> str:
        return self.message if self.code in self.message else f"{self.message} ({self.code})"

    def __reduce__(self):
        return (type(self), (self.code, self.message, self.discrepancy))


class QueryError(Error):
    """A query has no answer (unknown name, no path, a representation that cannot hold it, a
    compiled query whose edges were removed).

    code:     the stable snake_case error code, e.g. "unknown_frame", "no_pose_path",
              "query_invalidated"
    message:  what failed, naming the argument or the frames involved
    field:    the role at fault ("point", "orientation", "body", "ref_point", "ref_orientation",
              "ref_body", "coordinate_frame"), or None when no single argument is at fault
    argument: the keyword argument that supplied it ("of", "wrt", "expressed_in", ...), or None
    """

    def __init__(self, code: str, message: str, field: Optional[str] = None,
                 argument: Optional[str] = None) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.field = field
        self.argument = argument

    def __str__(self) -> str:
        return f"{self.message} ({self.code})"

    def __reduce__(self):
        return (type(self), (self.code, self.message, self.field, self.argument))


class ScriptError(Error, ValueError):
    """A scene script is malformed (bad YAML, unknown op or field, wrong types); nothing was
    applied. str() is the semgraph tool's "FILE:LINE:COLUMN: message" line.

    line, column: 1-based position of the offending node; message: what is wrong
    """

    def __init__(self, text: str, line: int, column: int, message: str) -> None:
        super().__init__(text)
        self.line = line
        self.column = column
        self.message = message

    def __reduce__(self):
        return (type(self), (str(self), self.line, self.column, self.message))


class BagError(Error):
    """A bag cannot be read or is corrupt (semgraph.ros); nothing was applied. str() is the
    semgraph tool's "FILE: byte OFFSET: MESSAGE (CODE)" line.

    code:    "io", "unknown_format", "truncated", "malformed", "crc_mismatch", "over_limit",
             "decompression" or "unsupported"
    file:    the path as given
    offset:  the byte offset in the file where the problem is (0 when not known: io, sqlite3)
    message: what is wrong, e.g. "record length 9999 past the end (120 left)"
    """

    def __init__(self, code: str, file: str, offset: int, message: str) -> None:
        super().__init__(f"{file}: byte {offset}: {message} ({code})")
        self.code = code
        self.file = file
        self.offset = offset
        self.message = message

    def __reduce__(self):
        return (type(self), (self.code, self.file, self.offset, self.message))
