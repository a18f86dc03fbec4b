"""The input files' and the ``--json`` output's schemas on the site: JSON Schema files and field tables.

At build time the path file's, the robot sidecar's and the cell file's JSON Schemas are written from their pydantic
models (``model_json_schema``) to ``_build_generated/extra/schemas/`` (served at the site's ``schemas/``, for
editors: ``# yaml-language-server: $schema=...``), beside ``docs/schemas/result.schema.json``, the ``--json``
output's schema that ``tests/output/test_json_schema.py`` validates real output against.

The directive ``schema-fields`` draws a schema's fields as tables, one per object type::

    ```{schema-fields} placement.robot.sidecar.Sidecar
    ```
    ```{schema-fields} schemas/result.schema.json
    ```
"""

from __future__ import annotations

import importlib
import json
import re
import shutil
from pathlib import Path
from typing import Any

from docutils import nodes
from docutils.parsers.rst import Directive
from sphinx.application import Sphinx

MODELS = {"path": "placement.path.path_file.PathFile", "sidecar": "placement.robot.sidecar.Sidecar",
          "cell": "placement.cell.cell_file.CellFile"}


def model_schema(dotted: str) -> dict[str, Any]:
    """The JSON Schema of the pydantic model named ``module.Class``."""
    module, _, name = dotted.rpartition(".")
    return getattr(importlib.import_module(module), name).model_json_schema()


def write_schemas(app: Sphinx) -> None:
    """Write every schema file into the folder the site serves at its root."""
    folder = Path(app.srcdir) / "_build_generated" / "extra" / "schemas"
    folder.mkdir(parents=True, exist_ok=True)
    for name, dotted in MODELS.items():
        schema = {"$schema": "https://json-schema.org/draft/2020-12/schema", **model_schema(dotted)}
        (folder / f"{name}.schema.json").write_text(json.dumps(schema, indent=2) + "\n", encoding="utf-8")
    shutil.copy(Path(app.srcdir) / "schemas" / "result.schema.json", folder / "result.schema.json")


def type_words(node: dict[str, Any]) -> str:
    """A schema node's type as a short phrase: ``number``, ``list of Actuator``, ``"point" | "weld"``, ..."""
    if "$ref" in node:
        return node["$ref"].rsplit("/", 1)[-1]
    if "const" in node:
        return json.dumps(node["const"])
    if "enum" in node:
        return " | ".join(json.dumps(value) for value in node["enum"])
    for key in ("anyOf", "oneOf"):
        if key in node:
            return " | ".join(dict.fromkeys(type_words(option) for option in node[key]))
    kind = node.get("type")
    if isinstance(kind, list):
        return " | ".join(kind)
    if kind == "array":
        if "prefixItems" in node:
            return "[" + ", ".join(type_words(item) for item in node["prefixItems"]) + "]"
        return f"list of {type_words(node.get('items', {}))}" if node.get("items") else "list"
    if kind == "object" and isinstance(node.get("additionalProperties"), dict) and "properties" not in node:
        return f"name → {type_words(node['additionalProperties'])}"
    words = kind or "any"
    bounds = [f"{op} {node[key]:g}" for key, op in (("minimum", "≥"), ("exclusiveMinimum", ">"), ("maximum", "≤"),
                                                    ("exclusiveMaximum", "<")) if key in node]
    return words + (f" ({', '.join(bounds)})" if bounds else "")


def objects(schema: dict[str, Any], title: str) -> list[tuple[str, dict[str, Any]]]:
    """Every object type of a schema with named fields: the root first, then its definitions (``$defs``), then
    objects nested in place (titled by their path, ``best.duty``), in order."""
    found: list[tuple[str, dict[str, Any]]] = []

    def visit(name: str, node: dict[str, Any]) -> None:
        if node.get("type") == "object" and "properties" in node:
            found.append((name, node))
            for field, sub in node["properties"].items():
                visit_nested(f"{name}.{field}", sub)
        for key in ("anyOf", "oneOf"):
            for option in node.get(key, []):
                visit(option.get("title", name), option)

    def visit_nested(name: str, node: dict[str, Any]) -> None:
        if node.get("type") == "object" and "properties" in node:
            visit(name, node)
        elif isinstance(node.get("items"), dict):
            visit_nested(f"{name}[]", node["items"])
        elif isinstance(node.get("additionalProperties"), dict):
            visit_nested(f"{name}.NAME", node["additionalProperties"])
        for key in ("anyOf", "oneOf"):
            for option in node.get(key, []):
                visit_nested(name, option)

    visit(title, schema)
    for name, node in schema.get("$defs", {}).items():
        visit(name, node)
    return found


def field_table(node: dict[str, Any], anchors: dict[str, str]) -> nodes.table:
    """A table of an object's fields: name (required ones marked), type (linked to the tables of the object types
    it names, ``anchors``: name → id), default, meaning."""
    required = set(node.get("required", []))
    table = nodes.table(classes=["schema-fields"])
    group = nodes.tgroup(cols=4)
    table += group
    for width in (18, 20, 10, 52):
        group += nodes.colspec(colwidth=width)
    head = nodes.thead()
    group += head
    body = nodes.tbody()
    group += body
    head += row(["field", "type", "default", "meaning"], literal=())
    for field, sub in node["properties"].items():
        default = json.dumps(sub["default"]) if "default" in sub else ("required" if field in required else "")
        line = row([field, type_words(sub), default, sub.get("description", sub.get("title", "")).strip()],
                   literal=(0, 2) if "default" in sub else (0,))
        line[1][0] = linked(type_words(sub), anchors)
        body += line
    return table


def linked(words: str, anchors: dict[str, str]) -> nodes.paragraph:
    """A type phrase with each object type it names linked to that type's table."""
    paragraph = nodes.paragraph()
    for token in re.split(r"([A-Za-z_][A-Za-z0-9_]*)", words):
        if token in anchors:
            reference = nodes.reference(refid=anchors[token], internal=True)
            reference += nodes.Text(token)
            paragraph += reference
        elif token:
            paragraph += nodes.Text(token)
    return paragraph


def row(cells: list[str], literal: tuple[int, ...]) -> nodes.row:
    """A table row: the cells at ``literal`` as code, the others as text whose ``double-backquoted`` words are code."""
    line = nodes.row()
    for index, text in enumerate(cells):
        entry = nodes.entry()
        entry += inline(text, code=index in literal and bool(text))
        line += entry
    return line


def inline(text: str, code: bool = False) -> nodes.paragraph:
    """A paragraph of ``text``: all code, or text with its ``double-backquoted`` parts as code."""
    paragraph = nodes.paragraph()
    if code:
        paragraph += nodes.literal(text=text)
        return paragraph
    for index, part in enumerate(text.split("``")):
        if part:
            paragraph += nodes.literal(text=part) if index % 2 else nodes.Text(part)
    return paragraph


class SchemaFields(Directive):
    """``schema-fields MODEL-OR-FILE``: a pydantic model's (dotted name) or a JSON Schema file's fields."""

    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        target = self.arguments[0]
        env = self.state.document.settings.env
        if target.endswith(".json"):
            file = Path(env.srcdir) / target
            env.note_dependency(str(file))
            schema = json.loads(file.read_text(encoding="utf-8"))
            title = schema.get("title", file.stem)
        else:
            schema = model_schema(target)
            title = target.rsplit(".", 1)[-1]
        out: list[nodes.Node] = []
        found = objects(schema, title)
        prefix = nodes.make_id(title)
        anchors = {name: f"{prefix}-{nodes.make_id(name)}" for name, _ in found if "." not in name and "[" not in name}
        for name, node in found:
            section = nodes.rubric(text=name)
            if name in anchors:
                section["ids"].append(anchors[name])
            out.append(section)
            if node.get("description"):
                out.append(inline(" ".join(node["description"].split())))
            out.append(field_table(node, anchors))
        return out


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("builder-inited", write_schemas)
    app.add_directive("schema-fields", SchemaFields)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
