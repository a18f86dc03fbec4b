"""RS-274/NGC lines parsed into words, parameter settings and O-words, with their expressions.

A line is read as LinuxCNC reads it: comments ``( ... )`` and after ``;`` removed, spaces and
case ignored, a leading ``/`` (block delete, off) and ``N`` line number skipped. A word's value is
a number, a parameter (``#5``, ``#<name>``, ``#[expr]``, ``##1``), an expression in brackets, a
unary function (``sin[30]``, ``atan[1]/[2]``), or any of them after a sign. Besides the letters,
LinuxCNC's polar words ``@`` (radius) and ``^`` (angle) are words.

Expressions in ``[ ]`` bind, from the tightest: ``**``; ``*``, ``/``, ``MOD``; ``+``, ``-``;
``EQ NE GT GE LT LE``; ``AND OR XOR``; operators of one rank bind left to right. Comparisons and
logic give 1 or 0 (``EQ`` and ``NE`` within 1e-4, as LinuxCNC); ``AND``/``OR``/``XOR`` take any
non-zero number as true; ``MOD`` takes the sign of the divisor's magnitude (as LinuxCNC). Angles of
``SIN COS TAN ASIN ACOS ATAN`` are in degrees; ``FIX`` rounds down, ``FUP`` up, ``ROUND`` half away
from zero; ``EXISTS[#<name>]`` is 1 if the named parameter is defined.

Expressions are compiled once per line into closures of a :class:`Parameters` store and evaluated
each time the line is executed (a line in a loop is parsed once).

A line starting with ``$`` is a grbl system command (``$H``, ``$X``, ``$$``, ``$J=...``), ``?`` grbl's status
query and ``G28 X Y`` (axis letters without numbers) Marlin's homing: each is kept whole for the reader to judge.
Marlin's messages (``M117 Cutting...``, ``M118``) are read as their M word alone: the rest of the line is their text.
Fanuc Macro B, which looks like RS-274/NGC but is not, is
refused by its own name: ``IF [...] THEN``/``GOTO``, ``WHILE [...] DO n``/``END n``, ``GOTO n``,
``DPRNT``/``BPRNT``/``POPEN``/``PCLOS``, expressions without brackets (``#1=#2+1``), the vacant ``#0`` and
Fanuc's system variables (``#5001``, the current X; ``#4001``, the active G codes ...) read before they are set.
A line that cannot be read and is in another controller's language (Heidenhain's conversational, Siemens
Sinumerik's: :mod:`placement.path.ngc_languages`) is refused naming that language and construct.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field

from placement.path.exceptions import _ExpressionError
from placement.path.ngc_languages import foreign_construct

EQUAL_TOLERANCE = 1e-4  # EQ and NE compare within this, as LinuxCNC's TOLERANCE_EQUAL
MAX_NUMBERED_PARAMETER = 5602  # LinuxCNC's numbered parameters are #1 to #5602
FANUC_SYSTEM_VARIABLES = (  # (first, last, meaning) of Fanuc Macro B's system variables a program reads
    (2001, 2400, "a tool offset"), (3000, 3000, "the alarm"), (3001, 3002, "a clock"),
    (3003, 3007, "a machine setting or mode"), (3011, 3012, "the date or time"), (3901, 3902, "the parts count"),
    (4001, 4130, "the modal state (the active G codes, D, F, H, M, S, T)"),
    (4201, 4330, "the modal state (the active G codes, D, F, H, M, S, T)"), (5001, 5008, "the current position"),
    (5021, 5028, "the machine position"), (5041, 5048, "the work position"), (5081, 5088, "the tool length offset"),
    (5101, 5108, "the servo deviation"))
FLOW = "expand the macro in the CAM post or use LinuxCNC O-word control flow"
FANUC_MACRO = (  # (start of a line, its construct's name, what to do instead) for Fanuc Macro B's words
    (re.compile(r"if\[.*\]then"), "'IF ... THEN'", f"{FLOW} (o100 if [...] ... o100 endif)"),
    (re.compile(r"if\[.*\]goto"), "'IF ... GOTO'", f"{FLOW} (o100 if [...], o100 while [...]: it has no jumps)"),
    (re.compile(r"if\["), "'IF'", f"{FLOW} (o100 if [...] ... o100 endif)"),
    (re.compile(r"while\["), "'WHILE ... DO'", f"{FLOW} (o100 while [...] ... o100 endwhile)"),
    (re.compile(r"end\d"), "'END' (closing a WHILE ... DO)", f"{FLOW} (o100 while [...] ... o100 endwhile)"),
    (re.compile(r"goto[\d#\[]"), "'GOTO'", f"{FLOW} (o100 if [...], o100 while [...]: it has no jumps)"),
    (re.compile(r"(dprnt|bprnt)\["), "'DPRNT'/'BPRNT' (output to a port)",
     "remove it (it writes to a port and does not move the tool)"),
    (re.compile(r"(popen|pclos)"), "'POPEN'/'PCLOS' (a port for DPRNT)",
     "remove it (it opens or closes a port and does not move the tool)"),
    (re.compile(r"setvn"), "'SETVN' (variable names)", "use named parameters (#<name>)"))
SUBROUTINE_PARAMETERS = 30  # a call's arguments are #1 to #30, local to the subroutine
NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)")
O_KEYWORDS = ("endsub", "sub", "call", "elseif", "else", "endif", "if", "endwhile", "while", "do", "endrepeat",
              "repeat", "return", "break", "continue")
FUNCTIONS: dict[str, Callable[[float], float]] = {
    "abs": abs, "acos": lambda x: math.degrees(math.acos(x)), "asin": lambda x: math.degrees(math.asin(x)),
    "cos": lambda x: math.cos(math.radians(x)), "exp": math.exp, "fix": lambda x: float(math.floor(x)),
    "fup": lambda x: float(math.ceil(x)), "ln": math.log, "round": lambda x: float(math.floor(abs(x) + 0.5)) * (
        1.0 if x >= 0 else -1.0), "sin": lambda x: math.sin(math.radians(x)), "sqrt": math.sqrt,
    "tan": lambda x: math.tan(math.radians(x))}
DOMAINS = {"acos": (-1.0, 1.0), "asin": (-1.0, 1.0), "ln": (0.0, math.inf), "sqrt": (0.0, math.inf)}
BINARY_RANK = {"**": 6, "*": 5, "/": 5, "mod": 5, "+": 4, "-": 4, "eq": 3, "ne": 3, "gt": 3, "ge": 3, "lt": 3,
               "le": 3, "and": 2, "or": 2, "xor": 2}
HASH_COMMENT = re.compile(r"\s*#\s")  # '# text', a comment in some firmwares' dialects
PLAIN_LINE = re.compile(r"(?:N[+-]?(?:\d+\.?\d*|\.\d+))?(?:[A-Z][+-]?(?:\d+\.?\d*|\.\d+))*")  # letters and numbers
PLAIN_WORD = re.compile(r"[A-Z][+-]?(?:\d+\.?\d*|\.\d+)")
SPACES = str.maketrans("", "", " \t\r")
PROGRAM_NAME = re.compile(r"[a-z][a-z0-9_.\-]*")  # a program's name in letters after O, as some controls write it
MARLIN_HOMING = re.compile(r"(?:N\d+)?(G0*28([XYZ]+))")  # Marlin's G28 with axis letters, no numbers: homes those
MARLIN_MESSAGE = re.compile(r"\s*/?\s*(?:N\s*\d+\s*)?M0*(11[78])(?![\d.])", re.IGNORECASE)  # M117, M118: text follows
POLAR = "@^"  # LinuxCNC's polar words: @ radius, ^ angle (degrees), in place of X and Y
SIGN_WORDS = POLAR + "$"  # words of a sign and a number: the polar words and LinuxCNC's spindle number ($0 in M3 $0)
OPERATOR_ORDER = sorted(BINARY_RANK, key=len, reverse=True)  # "**" before "*", "mod" before ...


@dataclass
class Parameters:
    """The parameter store: numbered parameters (0 until set), global named ones (``#<_name>``) and the
    named ones local to the running subroutine (or to the main program)."""

    numbered: dict[int, float] = field(default_factory=dict)
    globals: dict[str, float] = field(default_factory=dict)
    locals: dict[str, float] = field(default_factory=dict)

    def number(self, index: float, text: str) -> int:
        """A numbered parameter's index, checked."""
        if index == 0:
            raise _ExpressionError(text, "#0 is Fanuc Macro B's vacant (null) value, which RS-274/NGC does not have "
                                         f"(its parameters are #1 to #{MAX_NUMBERED_PARAMETER})")
        if index != int(index) or not 1 <= index <= MAX_NUMBERED_PARAMETER:
            raise _ExpressionError(text, f"parameter number {index:g} is not a whole number from 1 to "
                                        f"{MAX_NUMBERED_PARAMETER}")
        return int(index)

    def get(self, index: float, text: str) -> float:
        """The value of ``#index`` (0 until set; Fanuc Macro B's system variables are refused until set)."""
        number = self.number(index, text)
        if number not in self.numbered:
            meaning = next((m for first, last, m in FANUC_SYSTEM_VARIABLES if first <= number <= last), None)
            if meaning is not None:
                raise _ExpressionError(text, f"#{number} is read before it is set: on Fanuc controls it is a Fanuc "
                                             f"Macro B system variable ({meaning}), which RS-274/NGC does not have; "
                                             "expand the macro in the CAM post")
        return self.numbered.get(number, 0.0)

    def named(self, name: str, text: str) -> float:
        """The value of ``#<name>``; an undefined name is an error, as in LinuxCNC."""
        scope = self.globals if name.startswith("_") else self.locals
        if name not in scope:
            raise _ExpressionError(text, f"the named parameter #<{name}> is read before it is set")
        return scope[name]

    def exists(self, name: str) -> bool:
        """Whether ``#<name>`` is defined."""
        return name in (self.globals if name.startswith("_") else self.locals)

    def set_named(self, name: str, value: float) -> None:
        """Set ``#<name>`` in its scope."""
        (self.globals if name.startswith("_") else self.locals)[name] = value


Value = Callable[[Parameters], float]


@dataclass(frozen=True)
class Word:
    """A word of a line: its letter (lower case), its value's expression and its text as written (upper case)."""

    letter: str
    value: Value
    text: str


@dataclass(frozen=True)
class Assignment:
    """``#ref = value``: the parameter (a number's expression, or a name) and the value."""

    index: Value | None
    name: str | None
    value: Value
    text: str


@dataclass(frozen=True)
class OWord:
    """An O-word: its name (``100`` or ``<name>``), keyword and bracketed arguments or condition."""

    name: str
    keyword: str
    arguments: tuple[Value, ...]
    text: str


@dataclass(frozen=True)
class Block:
    """One line, read."""

    words: tuple[Word, ...] = ()
    assignments: tuple[Assignment, ...] = ()
    oword: OWord | None = None
    tape_mark: bool = False
    error: _ExpressionError | None = None  # a line that cannot be read: refused when it runs (not after M2, M30)
    system: str = ""  # a grbl system command ("$H", "$J=G91X10F100"), in upper case without spaces


def read_line(line: str) -> Block:
    """Read one line of a program; a line that cannot be read is a block holding its error, raised only if it runs
    (as LinuxCNC reads a line when it runs it: text after M2 or M30 is not read)."""
    try:
        return _read_line(line)
    except _ExpressionError as error:
        foreign = foreign_construct(line)
        if foreign is not None:
            return Block(error=_ExpressionError("", foreign))
        if HASH_COMMENT.match(line):
            return Block(error=_ExpressionError("#", "'#' starts a parameter in RS-274 (#1, #<name>), not a comment: "
                                                     "write comments in parentheses or after ';'"))
        if line.lstrip().startswith("//"):
            return Block(error=_ExpressionError("//", "'//' starts no comment in RS-274 (a leading '/' deletes the "
                                                      "block; '//' is a comment in some controls' dialects, such as "
                                                      "MillMaster Pro's): write comments in parentheses or after ';'"))
        return Block(error=error)


def _read_line(line: str) -> Block:
    """Read one line of a program.

    Raises:
        _ExpressionError: A malformed word, number, expression or comment.
    """
    message = MARLIN_MESSAGE.match(line)
    if message is not None:
        return Block((Word("m", lambda p: float(message.group(1)), f"M{message.group(1)}"),))
    compact = _strip(line)
    if compact.startswith("/"):
        compact = compact[1:]
    if compact == "%":
        return Block(tape_mark=True)
    if re.fullmatch(r":\d+", compact):
        return Block()  # ISO's program number (:1001), as Fanuc controls read it
    if compact.startswith("$") or compact == "?":  # grbl's system commands, and its status query
        return Block(system=compact)
    homing = MARLIN_HOMING.fullmatch(compact)
    if homing is not None:
        return Block(system=homing.group(1))
    if not compact.startswith("O") and PLAIN_LINE.fullmatch(compact):  # most lines a CAM post writes: read at once
        return Block(tuple(_plain_word(match.group()) for match in PLAIN_WORD.finditer(compact, _line_number(compact))))
    reader = _Reader(compact)
    return reader.block()


def _line_number(compact: str) -> int:
    """Where a plain line's words begin, after its N number if any."""
    match = NUMBER.match(compact, 1) if compact.startswith("N") else None
    return match.end() if match else 0


def _plain_word(text: str) -> Word:
    """A word of a letter and a number, as :class:`_Reader` reads it."""
    number = float(text[1:])
    return Word(text[0].lower(), lambda p: number, text)


def _strip(line: str) -> str:
    """The line without comments, spaces and tabs, in upper case."""
    if "(" not in line and ";" not in line:  # no comment: at once
        compact = line.translate(SPACES)
        if compact.isascii() and compact.isprintable():
            return compact.upper()
    code, depth = [], 0
    for char in line:
        if char == "(":
            if depth:
                raise _ExpressionError("", "a comment may not hold '(' (nested comments)")
            depth = 1
        elif char == ")" and depth:
            depth = 0
        elif char == ";" and not depth:
            break
        elif not depth and char not in " \t\r":
            if not char.isascii() or not char.isprintable():
                raise _ExpressionError(char, "a character outside comments that is not printable ASCII")
            code.append(char)
    if depth:
        raise _ExpressionError("", "the comment opened by '(' is not closed on its line")
    return "".join(code).upper()


class _Reader:
    """A recursive-descent reader of one compact line (upper case as written; matched in lower case)."""

    def __init__(self, text: str) -> None:
        self.text, self.low, self.at = text, text.lower(), 0

    def fail(self, start: int, problem: str) -> _ExpressionError:
        end = self.at if self.at > start else start + 1
        return _ExpressionError(self.text[start:end], problem)

    def peek(self, count: int = 1) -> str:
        return self.low[self.at:self.at + count]

    def block(self) -> Block:
        words: list[Word] = []
        assignments: list[Assignment] = []
        oword = None
        if self.peek() == "n":
            match = NUMBER.match(self.low, self.at + 1)
            self.at = match.end() if match else self.at + 1
        rest = self.low[self.at:]
        for pattern, construct, instead in FANUC_MACRO:
            if pattern.match(rest):
                raise _ExpressionError("", f"Fanuc Macro B {construct} is not read: {instead}")
        if self.peek() == "o":
            oword = self.oword()
        while self.at < len(self.low):
            start, char = self.at, self.peek()
            if char == "#":
                assignments.append(self.assignment())
            elif char.isalpha() or char in SIGN_WORDS:
                self.at += 1
                value = self.value()
                if self.peek() and not (self.peek().isalpha() or self.peek() in "#" + SIGN_WORDS):
                    operator = self.peek() in "+-*/"
                    while self.at < len(self.low) and not (self.low[self.at].isalpha() or self.low[self.at] in SIGN_WORDS):
                        self.at += 1
                    if operator:
                        raise self.fail(start, "an expression without brackets (Fanuc Macro B writes X#1+2): "
                                               "RS-274/NGC needs them, X[#1+2]")
                    raise self.fail(start, "expected a number after the letter (e.g. X12.5, G1), a parameter (#1, "
                                           "#<name>) or an expression in [ ]")
                words.append(Word(char, value, self.text[start:self.at]))
            else:
                self.at += 1
                raise self.fail(start, "expected a word: a letter and a number")
        return Block(tuple(words), tuple(assignments), oword)

    def oword(self) -> OWord | None:
        start = self.at
        self.at += 1
        if self.peek() == "<":
            end = self.low.find(">", self.at)
            if end < 0:
                raise self.fail(start, "an O-word name '<' is not closed by '>'")
            name, self.at = self.low[self.at:end + 1], end + 1
        else:
            match = re.compile(r"\d+").match(self.low, self.at)
            if match is None and PROGRAM_NAME.fullmatch(self.low, self.at):
                self.at = len(self.low)
                return None  # a program named in letters (OCIRCLE, as plasma and other controls write it): ignored
            if match is None:
                raise self.fail(start, "an O-word needs a number or a <name>")
            name, self.at = str(int(match.group())), match.end()
        keyword = next((k for k in O_KEYWORDS if self.low.startswith(k, self.at)), None)
        if keyword is None and not name.startswith("<"):
            if re.compile(r"[a-z_\-]+").fullmatch(self.low, self.at):
                self.at = len(self.low)  # a program name ending in letters (O7997A): ignored
            return None  # a program number (Fanuc's O0001), read and ignored
        if keyword is None:
            raise self.fail(start, f"an O-word needs one of {', '.join(sorted(O_KEYWORDS))}")
        self.at += len(keyword)
        arguments = []
        while self.peek() == "[":
            arguments.append(self.bracketed())
        if self.at < len(self.low):
            raise self.fail(self.at, f"unexpected text after 'O{name} {keyword}'")
        return OWord(name, keyword, tuple(arguments), self.text[start:self.at])

    def assignment(self) -> Assignment:
        start = self.at
        self.at += 1
        name, index = None, None
        if self.peek() == "<":
            name = self.name()
        else:
            index = self.value()
        if self.peek() != "=":
            raise self.fail(start, "a parameter outside a word must be set: #1=..., #<name>=...")
        self.at += 1
        value = self.value()
        if self.peek() and self.peek() in "+-*/":
            while self.at < len(self.low) and not self.low[self.at].isalpha() and self.low[self.at] != "#":
                self.at += 1
            raise self.fail(start, "a Fanuc Macro B expression without brackets (#1=#2+1): RS-274/NGC needs them, "
                                   "#1=[#2+1]")
        return Assignment(index, name, value, self.text[start:self.at])

    def name(self) -> str:
        start = self.at
        end = self.low.find(">", self.at)
        if end < 0:
            raise self.fail(start, "a parameter name '#<' is not closed by '>'")
        self.at = end + 1
        return self.low[start + 1:end]

    def value(self) -> Value:
        """A real value: number, parameter, bracketed expression, unary function, or one of them signed."""
        start, char = self.at, self.peek()
        if char == "[":
            return self.bracketed()
        if char == "#":
            self.at += 1
            if self.peek() == "<":
                name = self.name()
                text = self.text[start:self.at]
                return lambda p: p.named(name, text)
            index = self.value()
            text = self.text[start:self.at]
            return lambda p: p.get(index(p), text)
        if char in "+-" and self.low[self.at + 1:self.at + 2] in ("[", "#") or (
                char in "+-" and self.low[self.at + 1:self.at + 2].isalpha()):
            self.at += 1
            inner = self.value()
            return inner if char == "+" else (lambda p: -inner(p))
        if char.isalpha():
            return self.function()
        match = NUMBER.match(self.low, self.at)
        if match is None:
            while self.at < len(self.low) and not self.low[self.at].isalpha():
                self.at += 1
            raise self.fail(start, "expected a number after the letter (e.g. X12.5, G1), a parameter (#1, #<name>) or "
                                   "an expression in [ ]")
        self.at = match.end()
        number = float(match.group())
        return lambda p: number

    def function(self) -> Value:
        start = self.at
        if self.low.startswith("exists[#<", self.at):
            self.at += len("exists[")
            name = self.name()
            if self.peek() != "]":
                raise self.fail(start, "EXISTS takes one named parameter: EXISTS[#<name>]")
            self.at += 1
            return lambda p: float(p.exists(name))
        if self.low.startswith("atan", self.at):
            self.at += 4
            over = self.bracketed()
            if self.peek() != "/":
                raise self.fail(start, "ATAN takes two expressions: ATAN[y]/[x]")
            self.at += 1
            under = self.bracketed()
            return lambda p: math.degrees(math.atan2(over(p), under(p)))
        found = next((n for n in sorted(FUNCTIONS, key=len, reverse=True) if self.low.startswith(n, self.at)), None)
        if found is None:
            match = re.compile(r"[a-z]+").match(self.low, self.at)
            self.at = match.end() if match else self.at + 1
            raise self.fail(start, f"unknown function: the functions are {', '.join(sorted([*FUNCTIONS, 'atan', 'exists']))}"
                                   f" (a word's letter must be followed by its value)")
        name = found
        self.at += len(name)
        argument = self.bracketed()
        text, function, domain = self.text[start:self.at], FUNCTIONS[name], DOMAINS.get(name)

        def apply(p: Parameters) -> float:
            x = argument(p)
            if domain is not None and not (domain[0] <= x <= domain[1] and (name != "ln" or x > 0)):
                raise _ExpressionError(text, f"{name.upper()} of {x:g} is undefined")
            return function(x)

        return apply

    def bracketed(self) -> Value:
        start = self.at
        if self.peek() != "[":
            raise self.fail(start, "expected '['")
        self.at += 1
        result = self.expression(start)
        if self.peek() != "]":
            raise self.fail(start, "an expression's '[' is not closed by ']'" if self.at >= len(self.low)
                            else "expected an operator or ']' in the expression")
        self.at += 1
        return result

    def expression(self, start: int) -> Value:
        """Operands and binary operators up to the closing bracket, by rank (left to right within one)."""
        operands = [self.value()]
        operators: list[tuple[str, str]] = []
        while self.peek() not in ("]", ""):
            at = self.at
            operator = next((o for o in OPERATOR_ORDER if self.low.startswith(o, self.at)), None)
            if operator is None:
                raise self.fail(at, "expected an operator (+ - * / ** MOD EQ NE GT GE LT LE AND OR XOR) or ']'")
            self.at += len(operator)
            while operators and BINARY_RANK[operators[-1][0]] >= BINARY_RANK[operator]:
                _reduce(operands, operators)
            operators.append((operator, self.text[at:self.at]))
            operands.append(self.value())
        while operators:
            _reduce(operands, operators)
        text = self.text[start:self.at + 1]
        inner = operands[0]

        def checked(p: Parameters) -> float:
            try:
                return inner(p)
            except (OverflowError, ValueError, ZeroDivisionError) as error:
                raise _ExpressionError(text, f"the expression cannot be evaluated: {error}") from None

        return checked


def _reduce(operands: list[Value], operators: list[tuple[str, str]]) -> None:
    """Replace the last two operands by the last operator applied to them."""
    operator, text = operators.pop()
    right, left = operands.pop(), operands.pop()
    operands.append(_binary(operator, text, left, right))


def _binary(operator: str, text: str, left: Value, right: Value) -> Value:
    """A binary operator's closure."""
    if operator == "/":
        def divide(p: Parameters) -> float:
            divisor = right(p)
            if divisor == 0:
                raise _ExpressionError(text, "division by zero")
            return left(p) / divisor
        return divide
    if operator == "mod":
        def modulo(p: Parameters) -> float:
            divisor = right(p)
            if divisor == 0:
                raise _ExpressionError(text, "MOD by zero")
            value = math.fmod(left(p), divisor)
            return value + abs(divisor) if value < 0 else value
        return modulo
    if operator == "**":
        def power(p: Parameters) -> float:
            base, exponent = left(p), right(p)
            if base < 0 and exponent != int(exponent):
                raise _ExpressionError(text, f"{base:g} ** {exponent:g}: a negative number to a fractional power")
            return float(base**exponent)
        return power
    simple: dict[str, Callable[[float, float], float]] = {
        "*": lambda a, b: a * b, "+": lambda a, b: a + b, "-": lambda a, b: a - b,
        "eq": lambda a, b: float(abs(a - b) < EQUAL_TOLERANCE), "ne": lambda a, b: float(abs(a - b) >= EQUAL_TOLERANCE),
        "gt": lambda a, b: float(a > b), "ge": lambda a, b: float(a >= b), "lt": lambda a, b: float(a < b),
        "le": lambda a, b: float(a <= b), "and": lambda a, b: float(a != 0 and b != 0),
        "or": lambda a, b: float(a != 0 or b != 0), "xor": lambda a, b: float((a != 0) != (b != 0))}
    function = simple[operator]
    return lambda p: function(left(p), right(p))
