"""What a program's `--ros-args` say (rclpy's rcl arguments): parameter overrides (`-p name:=value`,
`-p node:name:=value`, `--params-file FILE`), the node's name and namespace (`-r __node:=NAME`,
`-r __ns:=NS`) and names remapped (`-r from:=to`); the process's own, read by rclpy.init(), and a
node's `cli_args`."""

from __future__ import annotations

from typing import Any

from rosclient import process

_global: list[Arguments | None] = [None]  # the program's, from rclpy.init()


def set_global(argv: list[str]) -> None:
    _global[0] = Arguments(process.program_args(argv)[1])


class Arguments:
    """What `--ros-args` says: parameter overrides (global and per node), the node's name and namespace,
    names remapped (`-r from:=to`)."""

    def __init__(self, ros_args: list[str]) -> None:
        self.parameters: dict[str, dict[str, Any]] = {}  # node ('' = every node) -> name -> value
        self.remapped_name: str | None = None
        self.namespace: str | None = None
        i = 0
        while i < len(ros_args):
            flag = ros_args[i]
            value = ros_args[i + 1] if i + 1 < len(ros_args) else None
            if flag in ("-p", "--param") and value and ":=" in value:
                key, text = value.split(":=", 1)
                node, _, name = key.rpartition(":")
                self.parameters.setdefault(node.strip("/"), {})[name] = process.parse_value(text)
                i += 2
            elif flag in ("-r", "--remap") and value and ":=" in value:
                key, text = value.split(":=", 1)
                if key.endswith("__node") or key.endswith("__name"):
                    self.remapped_name = text
                elif key.endswith("__ns"):
                    self.namespace = text
                else:  # a topic or service name remapped (from the default namespace)
                    process.remaps[process.resolve(key)] = process.resolve(text)
                i += 2
            elif flag == "--params-file" and value:
                self._params_file(value)
                i += 2
            else:
                i += 1

    def _params_file(self, path: str) -> None:
        import yaml

        with open(path, encoding="utf-8") as stream:
            data = yaml.safe_load(stream) or {}
        for node, body in data.items():
            values = (body or {}).get("ros__parameters", {})
            key = "" if node in ("/**", "**") else node.strip("/")
            self.parameters.setdefault(key, {}).update(_flatten(values))

    def parameters_for(self, fully_qualified: str, name: str) -> dict[str, Any]:
        out = dict(self.parameters.get("", {}))
        out.update(self.parameters.get(name, {}))
        out.update(self.parameters.get(fully_qualified.strip("/"), {}))
        return out


def _flatten(values: dict, prefix: str = "") -> dict[str, Any]:
    out = {}
    for key, value in values.items():
        if isinstance(value, dict):
            out.update(_flatten(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def arguments_for(cli_args: list[str] | None, use_global: bool) -> Arguments:
    merged = Arguments([])
    sources = []
    if use_global and _global[0] is not None:
        sources.append(_global[0])
    if cli_args:
        sources.append(Arguments(process.program_args(["", *cli_args])[1] if "--ros-args" in cli_args else cli_args))
    for source in sources:
        for node, values in source.parameters.items():
            merged.parameters.setdefault(node, {}).update(values)
        merged.remapped_name = source.remapped_name or merged.remapped_name
        merged.namespace = source.namespace or merged.namespace
    return merged
