# SPDX-License-Identifier: Apache-2.0
"""okid-fmu: an FMI 2 identifier FMU for any structure, without a compiler.

The prebuilt FMI 2 identifier FMU (the paper's configuration) holds one binary per platform; its
binary reads resources/okid_identifier.cfg at instantiation (the structural parameters num_inputs,
num_outputs, max_modes, num_singular_values and any parameter defaults), checks the sizes against
its build limits and the GUID against the configuration (sizes and a hash of the file). This
command writes that file and the matching modelDescription.xml, from the variable table the binary
was built from (documentation/model_variables.json of the prebuilt FMU):

    okid-fmu --inputs 2 --outputs 6 --max-modes 3 --observer-order 10 --order 6 -o frame.fmu

The description text is the same, byte for byte, as the C generator's (fmu/common/
make_model_description.c) for the same configuration; tests/python/test_fmu.py compares them.
"""
import argparse
import json
import math
import os
import re
import sys
import zipfile
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple

CONFIG_NAME = "okid_identifier.cfg"
LOG_CATEGORIES = [("logEvents", "identifications and other events"),
                  ("logStatusWarning", "rejected samples and other warnings"),
                  ("logStatusError", "refused calls and parameters, with the reason"),
                  ("logAll", "everything")]


def packaged_fmu_dir() -> Path:
    """The FMUs the wheel carries (okid/fmu: fmi2/ and fmi3/, written by scripts/wheel.sh)."""
    return Path(__file__).resolve().parent.parent / "fmu"


def default_base() -> Path:
    """The prebuilt FMI 2 identifier: $OKID_FMU_DIR/fmi2, the wheel's okid/fmu/fmi2, an installed
    share/okid/fmu/fmi2, or the build tree."""
    candidates = []
    if os.environ.get("OKID_FMU_DIR"):
        candidates.append(Path(os.environ["OKID_FMU_DIR"]) / "fmi2" / "okid_identifier.fmu")
    candidates += [packaged_fmu_dir() / "fmi2" / "okid_identifier.fmu",
                   Path(sys.prefix) / "share" / "okid" / "fmu" / "fmi2" / "okid_identifier.fmu",
                   Path("build") / "fmu" / "fmi2" / "okid_identifier.fmu"]
    return next((c for c in candidates if c.is_file()), candidates[-1])


def fnv1a(data: bytes) -> int:
    h = 2166136261
    for b in data:
        h = ((h ^ b) * 16777619) & 0xFFFFFFFF
    return h


def c_double(x: float) -> str:
    """printf("%.17g") of a double (Python's formatting is correctly rounded, as glibc's is)."""
    return "%.17g" % x


def escape(text: str) -> str:
    return text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;").replace(">", "&gt;")


def config_text(values: Sequence[Tuple[str, Any]]) -> str:
    """The resources configuration: one 'name value' line per setting, in table order."""
    lines = [f"{name} {c_double(value) if isinstance(value, float) else value}" for name, value in values]
    return "# okid identifier FMU configuration (written by okid-fmu; the GUID binds it)\n" + "\n".join(lines) + "\n"


def parse_config(text: str) -> Dict[str, float]:
    values: Dict[str, float] = {}
    for line in text.splitlines():
        fields = line.split()
        if fields and not fields[0].startswith("#"):
            values[fields[0]] = float(fields[1])
    return values


class Table:
    """The identifier's variable table (model_variables.json) with a configuration applied."""

    def __init__(self, table: Dict[str, Any], config: str = ""):
        self.table = table
        self.vars: List[Dict[str, Any]] = table["variables"]
        self.values: Dict[str, Any] = {v["name"]: v["start"] for v in self.vars if v["start"] is not None}
        for name, value in parse_config(config).items():
            self.values[name] = value
        self.hash: int = fnv1a(config.encode()) if config else 0

    def size(self, v: Dict[str, Any]) -> int:
        if not v["dims"]:
            return 1
        n = 1
        for d in v["dims"]:
            n *= d if isinstance(d, int) else int(self.values[d])
        return n

    def flat(self) -> Iterator[Tuple[Dict[str, Any], int, str]]:
        """(variable, element index, FMI 2 name) in value-reference order."""
        for v in self.vars:
            size = self.size(v)
            if not v["dims"]:
                yield v, 0, v["name"]
                continue
            first = v["dims"][0]
            outer = first if isinstance(first, int) else int(self.values[first])
            inner = size // max(outer, 1)
            for e in range(size):
                indices = iter([e // max(inner, 1) + 1, e % max(inner, 1) + 1])
                yield v, e, re.sub("%d", lambda _: str(next(indices)), v["flat_name"])

    def token(self) -> str:
        s = {k: int(self.values[k]) for k in ("num_inputs", "num_outputs", "max_modes", "num_singular_values")}
        base = f"okid-identifier-{self.table['generation_tool'].split()[-1]}"
        core = f"{base}-r{s['num_inputs']}-m{s['num_outputs']}-modes{s['max_modes']}-sv{s['num_singular_values']}"
        return "{" + core + (f"-config{self.hash:08x}" if self.hash else "") + "}"

    def start_text(self, v: Dict[str, Any]) -> str:
        value = self.values.get(v["name"], 0.0)
        if v["type"] == "real":
            return c_double(float(value))
        if v["type"] == "boolean":
            return "true" if value else "false"
        return "%d" % int(value)

    def range_text(self, v: Dict[str, Any]) -> str:
        out = ""
        for key in ("min", "max"):
            x = v[key]
            if x is not None and math.isfinite(x):
                out += f' {key}="{c_double(x) if v["type"] == "real" else "%.0f" % x}"'
        return out

    def fmi2(self, sources: Sequence[str]) -> str:
        t = self.table
        xml = ['<?xml version="1.0" encoding="UTF-8"?>',
               f'<fmiModelDescription fmiVersion="2.0" modelName="{escape(t["model"])}" '
               f'description="{escape(t["description"])}" generationTool="{t["generation_tool"]}" '
               f'guid="{escape(self.token())}" variableNamingConvention="flat" numberOfEventIndicators="0">',
               f'  <CoSimulation modelIdentifier="{t["model"]}" canHandleVariableCommunicationStepSize='
               f'"{"true" if t["variable_step"] else "false"}" canBeInstantiatedOnlyOncePerProcess="false" '
               'canNotUseMemoryManagementFunctions="false" canGetAndSetFMUstate="true" '
               f'canSerializeFMUstate="{"true" if t.get("can_serialize_state") else "false"}">',
               "    <SourceFiles>"]
        xml += [f'      <File name="{s}"/>' for s in sources
                if (s.endswith(".c") and len(s) > 2) or (s.endswith(".cpp") and len(s) > 4)]
        xml += ["    </SourceFiles>", "  </CoSimulation>"]
        units = []
        for v in self.vars:
            if v["unit"] and v["unit"] not in units:
                units.append(v["unit"])
        if units:
            xml += ["  <UnitDefinitions>"] + [f'    <Unit name="{u}"/>' for u in units] + ["  </UnitDefinitions>"]
        xml += ["  <LogCategories>"] + [f'    <Category name="{n}" description="{d}"/>' for n, d in LOG_CATEGORIES]
        xml += ["  </LogCategories>",
                f'  <DefaultExperiment startTime="0" stopTime="10" stepSize="{c_double(float(self.values["dt"]))}"/>',
                "  <ModelVariables>"]
        causality = {"structural": "calculatedParameter", "parameter": "parameter", "input": "input", "output": "output"}
        kinds = {"real": "Real", "boolean": "Boolean"}
        outputs, initial, first = [], [], {}
        for vr, (v, e, name) in enumerate(self.flat(), start=1):
            first.setdefault(v["name"], vr)
            line = (f'    <!-- {vr} -->\n    <ScalarVariable name="{escape(name)}" valueReference="{vr}" '
                    f'causality="{causality[v["causality"]]}" variability="{v["variability"]}"')
            if v["causality"] == "parameter":
                line += ' initial="exact"'
            if v["causality"] == "structural":
                line += ' initial="calculated"'
            line += f' description="{escape(v["description"])}">\n      <{kinds.get(v["type"], "Integer")}'
            if v["causality"] == "parameter":
                line += f' start="{self.start_text(v)}"'
            elif v["causality"] == "input":
                line += f' start="{c_double(0.0) if v["type"] == "real" else 0}"'
            if v["type"] != "boolean":
                line += self.range_text(v)
            if v["unit"]:
                line += f' unit="{v["unit"]}"'
            xml.append(line + "/>\n    </ScalarVariable>")
            if v["causality"] == "output":
                outputs.append((vr, v.get("depends_on")))
            if v["causality"] in ("output", "structural"):
                initial.append(vr)
        xml += ["  </ModelVariables>", "  <ModelStructure>", "    <Outputs>"]
        # direct dependencies on inputs as make_model_description.c writes them ("": none)
        sizes = {}
        for v, _, _ in self.flat():
            sizes[v["name"]] = sizes.get(v["name"], 0) + 1
        for i, on in outputs:
            if on is None:
                xml.append(f'      <Unknown index="{i}" dependencies=""/>')
            else:
                known = range(first[on], first[on] + sizes[on])
                xml.append(f'      <Unknown index="{i}" dependencies="{" ".join(map(str, known))}" '
                           f'dependenciesKind="{" ".join("fixed" for _ in known)}"/>')
        xml += ["    </Outputs>", "    <InitialUnknowns>"]
        xml += [f'      <Unknown index="{i}"/>' for i in initial]
        xml += ["    </InitialUnknowns>", "  </ModelStructure>", "</fmiModelDescription>"]
        return "\n".join(xml) + "\n"


def check_value(v: Mapping[str, Any], value: Any) -> Optional[str]:
    """A setting against its variable: a finite number, an integer for the integer kinds, within the
    variable's [min, max]. The refusal's text, or None."""
    name = v["name"]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return f"{name} = {value!r} is not a finite number"
    if v["type"] != "real" and value != int(value):
        return f"{name} = {value!r} is not an integer"
    low, high = v["min"], v["max"]
    if v["type"] == "boolean":
        low, high = 0, 1
    if (low is not None and value < low) or (high is not None and value > high):
        shown = lambda x: "" if x is None else (c_double(x) if v["type"] == "real" else "%.0f" % x)  # noqa: E731
        return f"{name} = {value!r} is outside {shown(low)}..{shown(high)}"
    return None


def check_identifier_config(values: Mapping[str, Any]) -> Optional[str]:
    """The okid_config the FMU's binary will run, checked by the C library itself (okid_config_check
    and its explanation, host_tools/common/config_explain.c): the refusal's text, or None."""
    from okid import _core

    if int(values["num_inputs"]) == 0:
        # output-only (okid_ambient): the binary checks hankel_rows, order, dt and sensing with
        # okid_ambient_config_check at initialization and names the refused one in its log
        return None
    cfg = _core.config_default(int(values["num_inputs"]), int(values["num_outputs"]))
    for name in cfg:
        if name in values:
            cfg[name] = type(cfg[name])(values[name])
    status, _, message = _core.explain_config(cfg)
    return None if status == 0 else message


def generate(base: Any, out: Any, settings: Sequence[Tuple[str, Any]]) -> str:
    """Writes the FMU `out` from the prebuilt FMI 2 FMU `base` for settings [(name, value), ...]
    (structural parameters and parameter defaults); returns the modelDescription text."""
    with zipfile.ZipFile(base) as z:
        table = json.loads(z.read("documentation/model_variables.json"))
        base_md = z.read("modelDescription.xml").decode()
        # the base's reference input and output are its configuration's: not this one's
        members = [(i, z.read(i)) for i in z.infolist()
                   if not i.filename.startswith(("modelDescription.xml", "resources/"))
                   and not i.filename.endswith(("_in.csv", "_ref.csv"))]
    known = {v["name"]: v for v in table["variables"] if v["causality"] in ("structural", "parameter")}
    for name, _ in settings:
        if name not in known:
            raise SystemExit(f"okid-fmu: '{name}' is not a structural parameter or parameter of {table['model']}")
    ordered = [(v["name"], dict(settings)[v["name"]]) for v in table["variables"] if v["name"] in dict(settings)]
    config = config_text(ordered)
    t = Table(table, config)
    for name in ("num_inputs", "num_outputs", "max_modes", "num_singular_values"):
        v, value = known[name], int(t.values[name])
        if not v["min"] <= value <= v["max"]:
            raise SystemExit(f"okid-fmu: {name} = {value} is outside this binary's range {v['min']:.0f}..{v['max']:.0f}")
    for name, value in settings:  # every value, before anything is written
        refused = check_value(known[name], value)
        if refused:
            raise SystemExit(f"okid-fmu: {refused}")
    refused = check_identifier_config(t.values)
    if refused:
        raise SystemExit(f"okid-fmu: {refused}")
    if Path(out).exists() and os.path.samefile(out, base):
        raise SystemExit(f"okid-fmu: the output {out} is the prebuilt FMU it is made from (--base): give another -o")
    sources = re.findall(r'<File name="([^"]+)"/>', base_md)
    text = t.fmi2(sources)
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("modelDescription.xml", text)
        z.writestr(f"resources/{CONFIG_NAME}", config)
        for info, data in members:
            z.writestr(info, data)
    return text


def enumeration(items: Sequence[str]) -> Callable[[str], int]:
    def parse(text: str) -> int:
        if text in items:
            return items.index(text)
        if text.isdigit() and int(text) < len(items):
            return int(text)
        raise argparse.ArgumentTypeError(f"'{text}' is not one of {', '.join(items)}")
    return parse


def main(argv: Optional[Sequence[str]] = None) -> int:
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--base", type=Path, default=None)
    known, _ = pre.parse_known_args(argv)
    base = known.base or default_base()
    parser = argparse.ArgumentParser(prog="okid-fmu", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", type=Path, default=base, help=f"the prebuilt FMI 2 identifier FMU (default {base})")
    parser.add_argument("--inputs", type=int, required=True, help="num_inputs r (forces); 0 = output-only (ambient) identification")
    parser.add_argument("--outputs", type=int, required=True, help="num_outputs m (sensors)")
    parser.add_argument("--max-modes", type=int, required=True, help="modes published")
    parser.add_argument("--singular-values", type=int, default=None, help="Hankel singular values published")
    parser.add_argument("-o", "--output", type=Path, required=True, help="the FMU to write")
    table = None
    if base.is_file():
        try:
            with zipfile.ZipFile(base) as z:
                table = json.loads(z.read("documentation/model_variables.json"))
        except (OSError, zipfile.BadZipFile, KeyError, ValueError) as exc:
            parser.error(f"--base {base} is no prebuilt okid identifier FMU ({exc})")
        for v in table["variables"]:  # every parameter of the vocabulary: --field-name
            if v["causality"] == "parameter":
                kind = float if v["type"] == "real" else int
                default = f"{v['start']:g}"
                if v.get("items"):  # enumerations by their item name (docs/cli.md) or C value
                    kind = enumeration(v["items"])
                    default = v["items"][int(v["start"])]
                parser.add_argument("--" + v["name"].replace("_", "-"), type=kind, default=None, dest=v["name"],
                                    help=f"{v['description']} (default {default})")
    args = parser.parse_args(argv)
    if table is None:
        parser.error(f"the prebuilt FMU {base} does not exist (build it, or give --base)")
    settings = [("num_inputs", args.inputs), ("num_outputs", args.outputs), ("max_modes", args.max_modes)]
    if args.singular_values is not None:
        settings.append(("num_singular_values", args.singular_values))
    for v in table["variables"]:
        if v["causality"] == "parameter" and getattr(args, v["name"]) is not None:
            settings.append((v["name"], getattr(args, v["name"])))
    try:
        generate(base, args.output, settings)
    except (OSError, zipfile.BadZipFile, KeyError) as exc:  # one line, never a traceback
        raise SystemExit(f"okid-fmu: {exc}") from None
    print(f"okid-fmu: wrote {args.output} (r = {args.inputs}, m = {args.outputs}, {args.max_modes} modes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
