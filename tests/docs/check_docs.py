#!/usr/bin/env python3
"""Holds the README and docs/ to their word (ctest label docs):

- every relative link names a file that exists, and a '#anchor' a heading of that file;
- every command they quote parses: `visfield`, `visfield-bench` and `visfield-experiments` (in sh blocks, and in
  inline code that is a command rather than a synopsis) are run with VISFIELD_PARSE_ONLY=1, which
  checks the command line and stops before any work; a script they run exists; a CMake preset they
  name is in CMakePresets.json.

Usage: check_docs.py --root SOURCE_DIR --visfield PATH [--bench PATH] [--experiments PATH] [--cuda]
"""

import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

LINK = re.compile(r"(?<!\!)\[(?:[^\]]*)\]\(([^)\s]+)\)|!\[(?:[^\]]*)\]\(([^)\s]+)\)")
INLINE_CODE = re.compile(r"`([^`]+)`")


def markdown_files(root):
    files = [os.path.join(root, "README.md")]
    docs = os.path.join(root, "docs")
    files += sorted(os.path.join(docs, f) for f in os.listdir(docs) if f.endswith(".md"))
    return files


def split_code(text):
    """(prose lines with their numbers, sh code blocks as (first line number, text))."""
    prose, blocks = [], []
    in_block, language, start, body = False, "", 0, []
    for number, line in enumerate(text.split("\n"), 1):
        if line.startswith("```"):
            if in_block:
                blocks.append((language, start, "\n".join(body)))
                in_block, body = False, []
            else:
                in_block, language, start = True, line[3:].strip(), number + 1
            continue
        if in_block:
            body.append(line)
        else:
            prose.append((number, line))
    return prose, blocks


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation but '-' and '_' dropped, spaces to '-'."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text, flags=re.UNICODE)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        prose, _ = split_code(open(path, encoding="utf-8").read())
        seen, found = {}, set()
        for _, line in prose:
            m = re.match(r"^#{1,6}\s+(.*)$", line)
            if not m:
                continue
            base = slug(m.group(1))
            n = seen.get(base, 0)
            found.add(base if n == 0 else f"{base}-{n}")
            seen[base] = n + 1
        cache[path] = found
    return cache[path]


def check_links(path, prose, errors):
    folder = os.path.dirname(path)
    for number, line in prose:
        # Links inside inline code are text, not links.
        for m in LINK.finditer(INLINE_CODE.sub("", line)):
            target = m.group(1) or m.group(2)
            if re.match(r"^[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            target_path = os.path.normpath(os.path.join(folder, file_part)) if file_part else path
            where = f"{os.path.relpath(path)}:{number}"
            if not os.path.exists(target_path):
                errors.append(f"{where}: link to {target}: no such file")
            elif anchor and target_path.endswith(".md") and anchor not in anchors(target_path):
                errors.append(f"{where}: link to {target}: no heading with that anchor")


def commands_in(prose, blocks):
    """(line number, command text): sh-block commands (continuations joined, comments dropped) split
    at && and ;, and inline code spans that are commands, not synopses."""
    out = []
    for language, start, body in blocks:
        if language not in ("sh", "bash", "console"):
            continue
        joined, first = "", None
        for offset, line in enumerate(body.split("\n")):
            if first is None:
                first = start + offset
            joined += line.rstrip("\\").rstrip() + " " if line.rstrip().endswith("\\") else line
            if line.rstrip().endswith("\\"):
                continue
            text = "" if joined.lstrip().startswith("#") else re.sub(r"\s+#.*$", "", joined).strip()
            for part in split_commands(text):
                out.append((first, part))
            joined, first = "", None
    for number, line in prose:
        for m in INLINE_CODE.finditer(line):
            code = m.group(1).strip()
            # A whole command, not a mention of one or of an option: it names a file or a scene.
            if (re.match(r"^(build/bin/)?visfield(-bench|-experiments)? ", code) and not re.search(r"[\[\]|…<>]|\.\.\.|[A-Z]{4,}", code)
                    and re.search(r"\s(--scene\s)?\S+\.[a-z]{3,6}\b|builtin:", code)):
                out.append((number, code))
    return out


OUTPUT_OPTIONS = {"--out", "-o", "--csv", "--plot", "--walk-plot", "--diff", "--save-measurements", "--frames-dir"}
FOLDER_OPTIONS = {"--models", "--walk-csv"}
TINY_PLY = """ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
element face 1
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
0 1 0
3 0 1 2
"""
WALK_CSV = "# visfield walk: bvh\nframe,update_ms,trace_ms,rays,rebuilt\n0,0.1,1.0,100,0\n1,0.1,1.0,100,0\n"


def png_1x1():
    """A valid 1x1 grey PNG."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(b"\x00\x80\x80\x80")) + chunk(b"IEND", b""))


class StandIns:
    """Valid files of every input kind the docs name by placeholder (a mesh, a moving scene, a walk
    CSV, a PNG, an ObjectField file): the command line is what is checked, and the tools read their
    inputs while they check it."""

    def __init__(self, root, visfield, folder):
        self.root = root
        tetra = os.path.join(root, "examples", "meshes", "tetra.obj")
        self.files = {".obj": open(tetra).read(), ".ply": TINY_PLY, ".csv": WALK_CSV}
        walk = open(os.path.join(root, "examples", "scenes", "walk.json")).read()
        self.files[".json"] = walk.replace("../meshes/", os.path.join(root, "examples", "meshes") + "/")
        self.binary = {".png": png_1x1()}
        field = os.path.join(folder, "stand-in.vfield")
        subprocess.run([visfield, "field", "build", tetra, "--positions", "290", "--directions", "8", "-o", field],
                       check=True, capture_output=True)
        self.binary[".vfield"] = open(field, "rb").read()

    def write(self, target):
        suffix = os.path.splitext(target)[1]
        os.makedirs(os.path.dirname(target), exist_ok=True)
        if suffix in self.binary:
            open(target, "wb").write(self.binary[suffix])
        elif suffix in self.files:
            open(target, "w").write(self.files[suffix])


def stage(scratch, root, args, stand_ins):
    """Makes `scratch` a place where a quoted command's placeholder paths resolve: the repository's
    examples/, an empty docs/images/, a stand-in for every input file named, and the folders that
    outputs and folder options name."""
    os.symlink(os.path.join(root, "examples"), os.path.join(scratch, "examples"))
    os.makedirs(os.path.join(scratch, "docs", "images"))
    for i, arg in enumerate(args):
        previous = args[i - 1] if i > 0 else ""
        target = os.path.join(scratch, arg)
        if arg.startswith("-") or os.path.exists(target):
            continue
        if arg.endswith("/") or previous in FOLDER_OPTIONS:
            os.makedirs(target, exist_ok=True)
        elif previous in OUTPUT_OPTIONS:
            os.makedirs(os.path.dirname(target) or scratch, exist_ok=True)
        elif "." in os.path.basename(arg):
            stand_ins.write(target)


def split_commands(text):
    """`text` cut at && and ; outside quotes."""
    parts, current, quote, i = [], "", None, 0
    while i < len(text):
        c = text[i]
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c == ";" or text.startswith("&&", i):
            parts.append(current.strip())
            current, i = "", i + (2 if c == "&" else 1)
            continue
        current += c
        i += 1
    parts.append(current.strip())
    return [p for p in parts if p]


def check_commands(path, prose, blocks, tools, root, presets, cuda, stand_ins, errors, counts):
    for number, command in commands_in(prose, blocks):
        where = f"{os.path.relpath(path)}:{number}"
        if "$(" in command or "`" in command:
            continue
        try:
            argv = shlex.split(command)
        except ValueError as e:
            errors.append(f"{where}: cannot split `{command}`: {e}")
            continue
        while argv and re.match(r"^[A-Z_]+=", argv[0]):  # environment assignments
            argv = argv[1:]
        if not argv:
            continue
        program = argv[0]
        name = os.path.basename(program)
        if name in ("visfield", "visfield-bench", "visfield-experiments"):
            tool = tools.get(name)
            if not tool:
                counts["skipped"] += 1
                continue
            if "--device" in argv and argv[argv.index("--device") + 1:][:1] == ["cuda"] and not cuda:
                counts["cuda"] += 1  # refused at parse by a build without CUDA
                continue
            env = dict(os.environ, VISFIELD_PARSE_ONLY="1")
            with tempfile.TemporaryDirectory() as scratch:
                stage(scratch, root, argv[1:], stand_ins)
                try:
                    result = subprocess.run([tool] + argv[1:], cwd=scratch, env=env, capture_output=True, text=True, timeout=60)
                except subprocess.TimeoutExpired:
                    errors.append(f"{where}: `{command}` ran past 60 s under VISFIELD_PARSE_ONLY=1 (is it honoured?)")
                    continue
            counts["commands"] += 1
            if result.returncode != 0:
                errors.append(f"{where}: `{command}` does not parse: {result.stderr.strip() or result.stdout.strip()}")
        elif program in ("bash", "sh", "/usr/bin/python3", "python3") and len(argv) > 1 and argv[1].startswith("scripts/"):
            counts["scripts"] += 1
            if not os.path.exists(os.path.join(root, argv[1])):
                errors.append(f"{where}: `{command}`: {argv[1]} does not exist")
        elif program.startswith("scripts/"):
            counts["scripts"] += 1
            if not os.path.exists(os.path.join(root, program)):
                errors.append(f"{where}: `{command}`: {program} does not exist")
        elif program == "cmake" and "--preset" in argv:
            preset = argv[argv.index("--preset") + 1]
            counts["presets"] += 1
            if preset not in presets:
                errors.append(f"{where}: `{command}`: no preset {preset} in CMakePresets.json")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--root", required=True)
    parser.add_argument("--visfield", required=True)
    parser.add_argument("--bench", default="")
    parser.add_argument("--experiments", default="")
    parser.add_argument("--cuda", action="store_true", help="the tools were built with CUDA")
    args = parser.parse_args()
    tools = {"visfield": args.visfield, "visfield-bench": args.bench, "visfield-experiments": args.experiments}
    presets_doc = json.load(open(os.path.join(args.root, "CMakePresets.json")))
    presets = {p["name"] for kind in ("configurePresets", "buildPresets", "testPresets") for p in presets_doc.get(kind, [])}
    errors, counts = [], {"commands": 0, "scripts": 0, "presets": 0, "skipped": 0, "cuda": 0}
    files = markdown_files(args.root)
    stand_in_folder = tempfile.TemporaryDirectory()
    stand_ins = StandIns(args.root, args.visfield, stand_in_folder.name)
    for path in files:
        prose, blocks = split_code(open(path, encoding="utf-8").read())
        check_links(path, prose, errors)
        check_commands(path, prose, blocks, tools, args.root, presets, args.cuda, stand_ins, errors, counts)
    for e in errors:
        print(e)
    print(f"check_docs: {len(files)} files; {counts['commands']} commands parsed, {counts['scripts']} scripts and "
          f"{counts['presets']} presets found; not run: {counts['skipped']} commands of a tool not built, "
          f"{counts['cuda']} --device cuda commands in a build without CUDA; {len(errors)} problems")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
