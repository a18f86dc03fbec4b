"""Validated YAML input files: strict pydantic models and errors that name file and field."""

from __future__ import annotations

import builtins
from pathlib import Path
from typing import Any, TypeVar

import yaml
from pydantic import BaseModel, ConfigDict, ValidationError

from placement.exceptions import InputFileError

Model = TypeVar("Model", bound=BaseModel)


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
    if not path.is_file():
        raise error(path, "", "file not found")
    try:
        raw = yaml.safe_load(path.read_text())
    except yaml.YAMLError as problem:
        raise error(path, "", f"not valid YAML: {problem}") from None
    if not isinstance(raw, dict):
        raise error(path, "", "expected a mapping of fields at the top level")
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
    return f"{message} (got {error['input']!r})"


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
