"""Other controllers' programming languages, which look like G-code in places but are not, recognised by name.

A Heidenhain conversational (Klartext) program moves the tool with ``L``, ``C`` and ``CC`` blocks, ``FMAX``
and ``R0``/``RL``/``RR``, calls tools with ``TOOL CALL`` and cycles with ``CYCL DEF``; a Siemens Sinumerik
program calls its cycles as functions (``CYCLE81(...)``, ``POCKET4(...)``), shifts and turns the coordinates
with frames (``TRANS``, ``ROT``, ``MIRROR``, ``SCALE``) and holds typed variables (``DEF REAL``) and R
parameters (``R1=...``). Read as RS-274/NGC their lines fail on a word that is not there, or worse, read as
something else (Sinumerik's ``CYCLE81(10,0,2,-25)`` would be the axis word C and a comment). A line in one of
these languages is refused naming the language and the construct, at its line, before it is read as words.
"""

from __future__ import annotations

import re

POST = "output the program with a G-code (ISO, RS-274) post of the CAM system"
HEIDENHAIN = "a Heidenhain conversational (Klartext) program"
SINUMERIK = "a Siemens Sinumerik program"
# (pattern of a line without spaces, in upper case, its N number left out; the language; the construct's name)
LANGUAGES = (
    (re.compile(r"\d*BEGINPGM"), HEIDENHAIN, "'BEGIN PGM'"),
    (re.compile(r"\d*ENDPGM"), HEIDENHAIN, "'END PGM'"),
    (re.compile(r"\d*BLKFORM"), HEIDENHAIN, "'BLK FORM' (the blank)"),
    (re.compile(r"\d*TOOLCALL"), HEIDENHAIN, "'TOOL CALL'"),
    (re.compile(r"\d*TOOLDEF"), HEIDENHAIN, "'TOOL DEF'"),
    (re.compile(r"\d*CYCLDEF"), HEIDENHAIN, "'CYCL DEF' (a cycle)"),
    (re.compile(r"\d*CYCLCALL"), HEIDENHAIN, "'CYCL CALL' (a cycle)"),
    (re.compile(r"\d*FUNCTIONTCPM"), HEIDENHAIN, "'FUNCTION TCPM' (5-axis tool centre point management)"),
    (re.compile(r"\d*LBL"), HEIDENHAIN, "'LBL' (a label)"),
    (re.compile(r"\d*CALLLBL"), HEIDENHAIN, "'CALL LBL' (a subprogram call)"),
    (re.compile(r"\d*FN\d+:"), HEIDENHAIN, "'FN' (a Q parameter function)"),
    (re.compile(r"\d*Q\d+=.*"), HEIDENHAIN, "a Q parameter"),
    (re.compile(r"\d*(L|C|CC|LP|CP|CT|RND|CHF)(?=[XYZIJKRF+\-]).*(FMAX|R0(?![\d.])|RL|RR)"), HEIDENHAIN,
     "a path block (L, C, CC, ... with R0/RL/RR or FMAX)"),
    (re.compile(r"%\w+G7[01]\*"), "a Heidenhain DIN/ISO program", "its start ('%NAME G71 *')"),
    (re.compile(r"(CYCLE|POCKET|SLOT|LONGHOLE|HOLES|CYCL)\d*\("), SINUMERIK, "a cycle call (CYCLE81(...), ...)"),
    (re.compile(r"MCALL"), SINUMERIK, "'MCALL' (a modal cycle call)"),
    (re.compile(r"A?(TRANS|ROT|SCALE|MIRROR)([XYZ]|RPL|$)"), SINUMERIK,
     "a frame (TRANS, ROT, SCALE, MIRROR and their A... forms)"),
    (re.compile(r"DEF(REAL|INT|BOOL|STRING|CHAR|AXIS|FRAME)"), SINUMERIK, "'DEF' (a variable definition)"),
    (re.compile(r"R\d+=.*"), SINUMERIK, "an R parameter"),
    (re.compile(r"T=\".*"), SINUMERIK, "a tool called by name (T=\"...\")"),
    (re.compile(r"TRAORI|TRAFOOF"), SINUMERIK, "'TRAORI' (5-axis transformation: the tool centre point programmed, "
     "the rotary axes following it; TRAFOOF ends it)"),
    (re.compile(r"(MSG\(|WORKPIECE\(|SUPA|CYCLE800|G500(?![\d.]))"), SINUMERIK,
     "a Sinumerik command (MSG, WORKPIECE, SUPA, G500, ...)"),
)
LINE_NUMBER = re.compile(r"N\d+")


def foreign_construct(line: str) -> str | None:
    """The refusal of a line in another controller's language, naming both, or None for any other line.

    Args:
        line: The line as written; a comment in parentheses or after ``;`` at its start is no construct.
    """
    code = line.strip().upper()
    if not code or code[0] in "(;":
        return None
    compact = code.replace(" ", "").replace("\t", "")
    number = LINE_NUMBER.match(compact)
    if number is not None:
        compact = compact[number.end():]
    for pattern, language, construct in LANGUAGES:
        if pattern.match(compact):
            return (f"{language}: {construct} is not RS-274 G-code, which is what is read; {POST}")
    return None
