"""Validated YAML input files: strict pydantic models and errors that name file and field."""

from __future__ import annotations

import builtins
import re
import reprlib
from pathlib import Path
from typing import Annotated, Any, TypeVar

import yaml
from pydantic import AfterValidator, BaseModel, ConfigDict, ValidationError
from pydantic import Strict as StrictValue

from placement.exceptions import InputFileError

Model = TypeVar("Model", bound=BaseModel)
MAX_FILE_BYTES = 10_000_000
MAX_NODES = 1_000_000  # values in a document once its aliases are expanded
MAX_DEPTH = 200  # nested mappings and lists in a document (a path's points are 3 deep)
_REPR = reprlib.Repr()  # bounded: never echo a whole input back
_REPR.maxlevel, _REPR.maxstring, _REPR.maxother, _REPR.maxlist, _REPR.maxdict, _REPR.maxtuple = 2, 60, 60, 4, 4, 4
Number = Annotated[float, StrictValue()]  # an integer or a decimal number; true and false are not numbers
Count = Annotated[int, StrictValue()]  # a whole number written as such


def _printable(text: str) -> str:
    if len(text) > 200 or any(ord(c) < 32 or ord(c) == 127 for c in text):
        raise ValueError("expected one line of printable text, at most 200 characters (it ends up in reports)")
    return text


Text = Annotated[str, AfterValidator(_printable)]


class Strict(BaseModel):
    """Base of every file schema: unknown fields are errors, values are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class Tagged(Strict):
    """Base of a plug-in family's schemas, whose ``type`` field names the member."""

    type: str

    @classmethod
    def schema_for(cls, value: Any) -> builtins.type[Tagged]:
        """The member schema the mapping ``value`` names by its ``type`` (this base when none)."""
        return cls


def read_yaml(path: Path, schema: type[Model], error: type[InputFileError]) -> Model:
    """Read a YAML file and validate it against ``schema``.

    Args:
        path: The file.
        schema: The pydantic model of the whole file.
        error: The exception class to raise (a subclass of InputFileError).

    Raises:
        InputFileError: (as ``error``) the file is missing, not YAML, or breaks the schema; the
            message names the field and what was expected.
    """
    if not str(path) or str(path) == ".":
        raise error(path, "", "empty file name")
    if not path.is_file():
        raise error(path, "", "not a regular file" if path.exists() else "file not found")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise error(path, "", f"the file is larger than {MAX_FILE_BYTES // 1_000_000} MB")
    try:
        raw = yaml.load(path.read_text(encoding="utf-8"), Loader=_UniqueKeyLoader)  # noqa: S506 (a SafeLoader)
    except UnicodeDecodeError:
        raise error(path, "", "not a text file in UTF-8") from None
    except RecursionError:
        raise error(path, "", "nested too deeply") from None
    except yaml.YAMLError as problem:
        if "nesting depth" in str(problem):  # the parser's own bound (PyYAML 6.0.4 on)
            raise error(path, "", f"nested too deeply (more than {MAX_DEPTH} levels)") from None
        raise error(path, "", f"not valid YAML: {_one_line(problem)}") from None
    return validate_document(raw, path, schema, error)


def validate_document(raw: Any, path: Path, schema: type[Model], error: type[InputFileError]) -> Model:
    """Validate a document already read (a file's YAML, or a dict given in Python) against ``schema``.

    Raises:
        InputFileError: (as ``error``, naming ``path``) not a mapping, too large, or breaks the schema; the
            message names the field and what was expected.
    """
    if not isinstance(raw, dict):
        raise error(path, "", "expected a mapping of fields at the top level")
    count, depth = _size(raw, MAX_NODES)
    if count > MAX_NODES:  # aliases can make a small file a huge document
        raise error(path, "", f"the document holds more than {MAX_NODES:,} values (counting each use of an & anchor)")
    if depth > MAX_DEPTH:  # the validation (and whatever reads the values) recurses through the nesting
        raise error(path, "", f"nested too deeply (more than {MAX_DEPTH} levels)")
    try:
        return schema.model_validate(raw)
    except ValidationError as problem:
        # An unknown field is usually a misspelt one: report it before the field it leaves missing.
        first = sorted(problem.errors(), key=lambda e: e["type"] != "extra_forbidden")[0]
        loc = tuple(part for part in first["loc"] if not _is_tag(schema, first["loc"], part))
        raise error(path, ".".join(map(str, loc)), _explain(schema, first, raw)) from None


def _explain(schema: type[BaseModel], error: Any, raw: Any) -> str:
    if error["type"] == "extra_forbidden":
        return f"unknown field; allowed here: {', '.join(_allowed_fields(schema, error['loc'][:-1], raw))}"
    if error["type"] == "missing":
        return "required field is missing"
    message = error["msg"].removeprefix("Value error, ")
    if "got " in message:  # a validator's own message already says what it found
        return message
    return f"{message} (got {_REPR.repr(error['input'])})"


def _is_tag(schema: type[BaseModel], loc: tuple[Any, ...], part: Any) -> bool:
    """Whether ``part`` of an error location is a discriminated-union tag, not a field."""
    annotation: Any = schema
    for item in loc:
        if item == part:
            return _union_member(annotation, item) is not None
        annotation = _step(annotation, item)
    return False


def _allowed_fields(schema: type[BaseModel], loc: tuple[Any, ...], raw: Any) -> list[str]:
    annotation: Any = schema
    for part in loc:
        annotation = _step(annotation, part)
        raw = raw.get(part) if isinstance(raw, dict) else raw[part] if isinstance(raw, list) else None
    model = _model_of(annotation)
    if isinstance(model, type) and issubclass(model, Tagged):
        model = model.schema_for(raw)  # a plug-in family member, named by the input's own tag
    return sorted(model.model_fields) if model else []


def _step(annotation: Any, part: Any) -> Any:
    """The annotation of the child ``part`` (field name, dict key, list index or union tag)."""
    origin = getattr(annotation, "__origin__", None)
    if origin is dict:
        return annotation.__args__[1]
    if origin is list:
        return annotation.__args__[0]
    member = _union_member(annotation, part)
    if member is not None:
        return member
    model = _model_of(annotation)
    field = model.model_fields.get(part) if model else None
    return field.annotation if field else None


def _union_member(annotation: Any, tag: Any) -> Any:
    """The member of a tagged union whose ``type`` literal is ``tag``, if any."""
    if hasattr(annotation, "__metadata__"):  # Annotated[Union, Field(discriminator=...)]: the union (a dict's values)
        annotation = annotation.__origin__
    for arg in getattr(annotation, "__args__", ()):
        if isinstance(arg, type) and issubclass(arg, BaseModel) and "type" in arg.model_fields:
            if tag in getattr(arg.model_fields["type"].annotation, "__args__", ()):
                return arg
    return None


def _model_of(annotation: Any) -> Any:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    if getattr(annotation, "__origin__", None) in (dict, list):
        return None
    for arg in getattr(annotation, "__args__", ()):
        found = _model_of(arg)
        if found is not None:
            return found
    return None


class _UniqueKeyLoader(getattr(yaml, "CSafeLoader", yaml.SafeLoader)):  # type: ignore[misc]
    """YAML's safe loader (libyaml's parser where PyYAML has it: 10 times faster on a path of 100,000 points),
    refusing a mapping that gives the same key twice, and reading 1e-3 as a number (as YAML 1.2 does; YAML 1.1
    wants 1.0e-3)."""

    yaml_implicit_resolvers = {key: list(value) for key, value in yaml.SafeLoader.yaml_implicit_resolvers.items()}

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen = set()
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":  # '<<: *anchor' keys may be overridden here
                continue
            key = self.construct_object(key_node, deep=deep)
            if not isinstance(key, (str, int, float, bool)) and key is not None:
                raise yaml.constructor.ConstructorError(None, None, "a key must be a plain name or number",
                                                        key_node.start_mark)
            if key in seen:
                raise yaml.constructor.ConstructorError(None, None, f"the key '{_short(str(key), 60)}' appears twice",
                                                        key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


def _size(document: Any, limit: int) -> tuple[int, int]:
    """How many values ``document`` holds, counting shared ones each time, and how deep it nests; stops past
    ``limit`` values."""
    count, depth, stack = 0, 0, [(document, 1)]
    while stack and count <= limit:
        node, level = stack.pop()
        count, depth = count + 1, max(depth, level)
        if isinstance(node, dict):
            stack.extend((value, level + 1) for value in node.values())
        elif isinstance(node, list):
            stack.extend((value, level + 1) for value in node)
    return count, depth


def _one_line(problem: yaml.YAMLError) -> str:
    """A YAML error as one line: what, and where (line and column, counted from 1)."""
    what = getattr(problem, "problem", None) or str(problem).splitlines()[0]
    mark = getattr(problem, "problem_mark", None)
    where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
    return _short(" ".join(f"{what}{where}".split()), 200)


def _short(text: str, length: int) -> str:
    return text if len(text) <= length else text[: length - 3] + "..."


_UniqueKeyLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float", re.compile(r"^[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)[eE][-+]?[0-9]+$"),
    list("-+0123456789."))
