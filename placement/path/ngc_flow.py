"""RS-274/NGC control flow within one program: O-word subroutines, conditions and loops.

The lines are run as LinuxCNC runs them: ``O<name> sub`` ... ``endsub`` defines a subroutine
(skipped where it stands) that ``O<name> call [a] [b] ...`` runs with ``#1``, ``#2`` ... set to the
arguments (``#1``-``#30`` and the named parameters not starting with ``_`` are its own and are
restored on return); ``return [v]`` and ``endsub [v]`` leave it (setting ``#<_value>``);
``if``/``elseif``/``else``/``endif``, ``while``/``endwhile``, ``do``/``while``,
``repeat [n]``/``endrepeat``, ``break`` and ``continue`` (each O-word naming its construct's
number or name). ``M2``, ``M30``, ``M99`` (in the main program) or a second ``%`` line ends the program;
a line that cannot be read is refused when it runs, so text after the program's end is not read. At most
``MAX_EXECUTED_BLOCKS`` lines are run, so a program that never ends is refused rather than
hanging. Subroutines in other files (LinuxCNC's search path) are not read.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from placement.path.exceptions import _ExpressionError, _FlowError
from placement.path.ngc_expressions import SUBROUTINE_PARAMETERS, Block, OWord, Parameters

MAX_EXECUTED_BLOCKS = 10_000_000
MAX_CALL_DEPTH = 100
LOOP_STARTS = ("while", "do", "repeat")


@dataclass
class _Frame:
    """A running subroutine: where to return, the caller's #1-#30 and local names."""

    return_to: int
    saved_numbered: dict[int, float]
    saved_locals: dict[str, float]
    repeats: dict[int, int] = field(default_factory=dict)


def run_blocks(blocks: list[Block], parameters: Parameters,
               execute: Callable[[int, list[tuple[str, float, str]], int], bool],
               system: Callable[[int, str], None]) -> None:
    """Run a program's lines in order of control flow.

    Args:
        blocks: The lines, read (:func:`placement.path.ngc_expressions.read_line`).
        parameters: The parameter store, changed as the lines set parameters.
        execute: Called with each line's index, its words (letter, value, text as written) after its parameter
            settings, and the depth of subroutine calls it runs in (0: the main program); returns False to end the
            program (M2, M30, M99 in the main program).
        system: Called with the index and text of each grbl system command (``$H``, ...) in its turn.

    Raises:
        _FlowError: Unmatched or misplaced O-words, a call of an unknown subroutine, too many lines run, or a
            line that cannot be evaluated (its ``_ExpressionError``, with the line's index).
        _ExpressionError: A line that cannot be read, when it runs (its ``index`` set).
    """
    flow = _Flow(blocks)
    main = _Frame(len(blocks), {}, {})
    frames = [main]
    index, executed, marks = 0, 0, 0
    while index < len(blocks):
        executed += 1
        if executed > MAX_EXECUTED_BLOCKS:
            raise _FlowError(index, "", f"more than {MAX_EXECUTED_BLOCKS:,} lines run: the program does not end "
                                       "(an endless loop?)")
        block = blocks[index]
        if block.error is not None:  # a line that cannot be read, reached
            block.error.index = index
            raise block.error
        try:
            if block.tape_mark:
                marks += 1
                if marks == 2:
                    return
                index += 1
                continue
            if block.oword is not None:
                index = flow.step(index, block.oword, parameters, frames)
                continue
            if block.system:
                system(index, block.system)
                index += 1
                continue
            words = [(word.letter, word.value(parameters), word.text) for word in block.words]
            values = [(a, a.value(parameters)) for a in block.assignments]
        except _ExpressionError as error:
            raise _FlowError(index, error.text, error.problem) from None
        for assignment, value in values:
            if assignment.name is not None:
                parameters.set_named(assignment.name, value)
            else:
                assert assignment.index is not None
                try:
                    number = parameters.number(assignment.index(parameters), assignment.text)
                except _ExpressionError as error:
                    raise _FlowError(index, error.text, error.problem) from None
                parameters.numbered[number] = value
        if words and not execute(index, words, len(frames) - 1):
            return
        index += 1
    if len(frames) > 1:
        raise _FlowError(len(blocks) - 1, "", "the program ends inside a subroutine (no endsub)")


class _Flow:
    """The O-words of a program, found by name and keyword, and what each does."""

    def __init__(self, blocks: list[Block]) -> None:
        self.owords = [(i, b.oword) for i, b in enumerate(blocks) if b.oword is not None]
        self.subs: dict[str, int] = {}
        self.do_ends: set[int] = set()  # the 'while' lines that close a 'do'
        open_dos: dict[str, list[int]] = {}
        for i, oword in self.owords:
            if oword.keyword == "sub":
                if oword.name in self.subs:
                    raise _FlowError(i, oword.text, f"subroutine O{oword.name} is defined twice")
                self.subs[oword.name] = i
            elif oword.keyword == "do":
                open_dos.setdefault(oword.name, []).append(i)
            elif oword.keyword == "while" and open_dos.get(oword.name):
                open_dos[oword.name].pop()
                self.do_ends.add(i)
        self.cache: dict[tuple[int, str, tuple[str, ...], bool], int] = {}
        self.keywords = {i: oword.keyword for i, oword in self.owords}
        closers = {"sub": ("endsub",), "if": ("endif",), "repeat": ("endrepeat",), "do": ("while",)}
        for i, oword in self.owords:  # every construct is closed (LinuxCNC checks as it runs)
            if oword.keyword == "while" and i not in self.do_ends:
                self.find(i, oword, ("endwhile",))
            elif oword.keyword in closers:
                self.find(i, oword, closers[oword.keyword])

    def find(self, at: int, oword: OWord, keywords: tuple[str, ...], forward: bool = True,
             do_end: bool | None = None) -> int:
        """The nearest line after (or before) ``at`` with this O-word name and one of the keywords."""
        key = (at, oword.name, keywords + (str(do_end),), forward)
        if key not in self.cache:
            lines = self.owords if forward else self.owords[::-1]
            found = next((i for i, o in lines if (i > at if forward else i < at) and o.name == oword.name
                          and o.keyword in keywords and (do_end is None or (i in self.do_ends) == do_end)), None)
            if found is None:
                raise _FlowError(at, oword.text, f"O{oword.name} {oword.keyword} has no matching "
                                                f"{' or '.join(keywords)} {'after' if forward else 'before'} it")
            self.cache[key] = found
        return self.cache[key]

    def step(self, at: int, oword: OWord, parameters: Parameters, frames: list[_Frame]) -> int:
        """Run an O-word line; the index of the next line to run."""
        keyword, frame = oword.keyword, frames[-1]

        def condition() -> bool:
            if len(oword.arguments) != 1:
                raise _FlowError(at, oword.text, f"O{oword.name} {keyword} needs one condition in [ ]")
            return oword.arguments[0](parameters) != 0

        if keyword == "sub":
            return self.find(at, oword, ("endsub",)) + 1
        if keyword in ("endsub", "return"):
            if len(frames) == 1:
                raise _FlowError(at, oword.text, f"O{oword.name} {keyword} outside a subroutine call")
            if oword.arguments:
                parameters.globals["_value"] = oword.arguments[0](parameters)
            frames.pop()
            parameters.numbered.update(frame.saved_numbered)
            parameters.locals = frame.saved_locals
            return frame.return_to
        if keyword == "call":
            if oword.name not in self.subs:
                raise _FlowError(at, oword.text, f"no subroutine O{oword.name} sub in this program (subroutines in other "
                                                "files are not read)")
            if len(frames) > MAX_CALL_DEPTH:
                raise _FlowError(at, oword.text, f"calls nested deeper than {MAX_CALL_DEPTH} (endless recursion?)")
            if len(oword.arguments) > SUBROUTINE_PARAMETERS:
                raise _FlowError(at, oword.text, f"more than {SUBROUTINE_PARAMETERS} arguments")
            arguments = [argument(parameters) for argument in oword.arguments]
            saved = {k: parameters.numbered.get(k, 0.0) for k in range(1, SUBROUTINE_PARAMETERS + 1)}
            frames.append(_Frame(at + 1, saved, parameters.locals))
            parameters.locals = {}
            for k in range(1, SUBROUTINE_PARAMETERS + 1):
                parameters.numbered[k] = arguments[k - 1] if k <= len(arguments) else 0.0
            return self.subs[oword.name] + 1
        if keyword == "if":
            if condition():
                return at + 1
            return self.skip_branch(at, oword, parameters)
        if keyword in ("elseif", "else"):  # the branch before ran: leave the construct
            return self.find(at, oword, ("endif",)) + 1
        if keyword == "endif" or keyword == "do":
            return at + 1
        if keyword == "while" and at in self.do_ends:
            return self.find(at, oword, ("do",), forward=False) + 1 if condition() else at + 1
        if keyword == "while":
            return at + 1 if condition() else self.find(at, oword, ("endwhile",)) + 1
        if keyword == "endwhile":
            return self.find(at, oword, ("while",), forward=False, do_end=False)
        if keyword == "repeat":
            if len(oword.arguments) != 1:
                raise _FlowError(at, oword.text, f"O{oword.name} repeat needs a count in [ ]")
            count = int(oword.arguments[0](parameters))
            if count <= 0:
                return self.find(at, oword, ("endrepeat",)) + 1
            frame.repeats[at] = count
            return at + 1
        if keyword == "endrepeat":
            start = self.find(at, oword, ("repeat",), forward=False)
            frame.repeats[start] = frame.repeats.get(start, 1) - 1
            if frame.repeats[start] > 0:
                return start + 1
            del frame.repeats[start]
            return at + 1
        # break, continue: the innermost loop of this name before the line
        start = self.find(at, oword, LOOP_STARTS, forward=False, do_end=False)
        kind = self.keywords[start]
        if kind == "while":
            end = self.find(start, oword, ("endwhile",))
        elif kind == "do":
            end = self.find(start, oword, ("while",), do_end=True)
        else:
            end = self.find(start, oword, ("endrepeat",))
        if keyword == "continue":
            return start if kind == "while" else end
        frame.repeats.pop(start, None)
        return end + 1

    def skip_branch(self, at: int, oword: OWord, parameters: Parameters) -> int:
        """After a false if or elseif: the first branch whose condition holds, else the else, else after endif."""
        while True:
            at = self.find(at, oword, ("elseif", "else", "endif"))
            following = next(o for i, o in self.owords if i == at)
            if following.keyword == "elseif":
                if len(following.arguments) != 1:
                    raise _FlowError(at, following.text, f"O{following.name} elseif needs one condition in [ ]")
                if following.arguments[0](parameters) != 0:
                    return at + 1
                continue
            return at + 1
