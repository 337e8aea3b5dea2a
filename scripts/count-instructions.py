#!/usr/bin/python3
"""Counts the instructions a command executes in the functions it names, by source line.

    /usr/bin/python3 scripts/count-instructions.py --collect 'PATTERN' [--file NAME] [--skip NAME] [--top N] -- COMMAND ...

Runs COMMAND under valgrind's callgrind, counting only inside functions whose names match PATTERN
(callgrind's --toggle-collect, e.g. 'vf::field::ObjectField::mark_occluded(*' or 'vf::field::occluded_batch(*'; name
the function from its start: callgrind stops counting inside a match called from a match, such as a lambda of
the named function, whose name contains the function's, and the script warns of such matches), and prints:
the total; the executed instructions that touch the stack (spills and reloads, with the arithmetic
that reads a spilled value) and the commonest mnemonics; and the instructions by source line, each
given to the innermost inlined frame whose file name contains NAME (default: the innermost frame
outside the system's headers and the files named by --skip), with its function. Counts are exact
and repeatable, where timings on a shared machine vary by 10% and more: they show where an A/B change removes work before a benchmark can.
They are not cycles (a gather or a division counts one). Build with debug lines for the attribution
(e.g. -DCMAKE_CXX_FLAGS=-g in a separate Release build folder); needs valgrind and binutils. Only
the command's own code is attributed; what runs in shared libraries is counted apart.
"""

import argparse
import collections
import fnmatch
import os
import re
import subprocess
import sys
import tempfile


def fail(message):
    print(f"count-instructions: error: {message}", file=sys.stderr)
    sys.exit(2)


def read_costs(path, binary):
    """Self instruction counts by address in `binary`, and the count in other objects (libraries),
    from a callgrind file written with --dump-instr=yes (addresses are per object)."""
    cost = collections.Counter()
    elsewhere = 0
    names = {}  # object ids to paths, as ob= and cob= lines define them
    ours = False
    address = 0
    call_line_next = False
    with open(path) as f:
        for line in f:
            m = re.match(r"(c?ob)=\((\d+)\)(?: (.*))?", line.rstrip("\n"))
            if m:
                if m.group(3):
                    names[m.group(2)] = m.group(3)
                if m.group(1) == "ob":
                    ours = os.path.realpath(names.get(m.group(2), "")) == binary
                continue
            if line.startswith("calls="):
                call_line_next = True  # the next cost line is the call's inclusive cost
                continue
            if not line or line[0] not in "0123456789+-*":
                continue
            parts = line.split()
            if len(parts) < 3:
                continue
            where = parts[0]
            if where.startswith("0x"):
                address = int(where, 16)
            elif where.startswith("+"):
                address += int(where[1:])
            elif where.startswith("-"):
                address -= int(where[1:])
            if call_line_next:
                call_line_next = False
                continue
            if ours:
                cost[address] += int(parts[2])
            else:
                elsewhere += int(parts[2])
    return cost, elsewhere


def disassemble(binary, addresses):
    """Mnemonic and operands of each address."""
    out = subprocess.run(["objdump", "-d", "--no-show-raw-insn", f"--start-address={min(addresses):#x}",
                          f"--stop-address={max(addresses) + 16:#x}", binary], capture_output=True, text=True, check=True).stdout
    found = {}
    for line in out.split("\n"):
        m = re.match(r"\s*([0-9a-f]+):\s+(\S+)\s*(.*)", line)
        if m:
            found[int(m.group(1), 16)] = (m.group(2), m.group(3))
    return found


def inline_chains(binary, addresses):
    """Each address's inlined frames, innermost first: [(function, file:line), ...]."""
    out = subprocess.run(["addr2line", "-a", "-i", "-f", "-C", "-e", binary] + [hex(a) for a in addresses],
                         capture_output=True, text=True, check=True).stdout.split("\n")
    chains, current, i = {}, None, 0
    while i < len(out):
        line = out[i]
        if line.startswith("0x"):
            current = int(line, 16)
            chains[current] = []
            i += 1
        elif line and current is not None and i + 1 < len(out):
            chains[current].append((line, out[i + 1].split(" ")[0]))
            i += 2
        else:
            i += 1
    return chains


def nested_matches(binary, pattern):
    """The binary's lambdas and local functions whose names (mangled or demangled) match `pattern`, when
    another function matches it too: callgrind turns counting off on entering each match and on again
    on leaving it, so a match called from a match (a lambda of the named function, a template made
    for one) is left out of the count."""
    def symbols(demangle):
        out = subprocess.run(["nm", "--defined-only"] + (["-C"] if demangle else []) + [binary],
                             capture_output=True, text=True).stdout.split("\n")
        return [line.split(" ", 2)[2] for line in out if line.count(" ") >= 2 and line.split(" ", 2)[1] in "tTwW"]
    mangled, demangled = symbols(False), symbols(True)
    if len(mangled) != len(demangled):
        return []
    matching = [(m, d) for m, d in zip(mangled, demangled) if fnmatch.fnmatchcase(m, pattern) or fnmatch.fnmatchcase(d, pattern)]
    inner = [d for m, d in matching if m.startswith("_ZZ") or "{lambda" in d]
    return inner if len(matching) > len(inner) else []


def short_name(function):
    """A demangled name without template arguments, parameters and namespaces: FieldKernel::dot."""
    out, depth = [], 0
    for ch in function:
        if ch in "<(":
            depth += 1
        elif ch in ">)":
            depth = max(depth - 1, 0)
        elif depth == 0:
            out.append(ch)
    parts = [p for p in "".join(out).split("::") if p and p not in ("vf", "field", "lanes", "bvh", "simd")]
    return "::".join(parts[-2:]) if parts else function


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--collect", required=True, help="callgrind --toggle-collect pattern")
    parser.add_argument("--file", default="", help="give each line to the innermost frame in a file whose name contains this")
    parser.add_argument("--skip", action="append", default=[],
                        help="pass over frames in files whose names contain this (helpers such as kernel_lanes.hpp); repeatable")
    parser.add_argument("--top", type=int, default=30, help="lines to print (default 30)")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        fail("no command given (after --)")
    if args.top < 1:
        fail(f"--top must be at least 1, not {args.top}")
    binary = command[0] if os.path.sep in command[0] else subprocess.run(["which", command[0]], capture_output=True, text=True).stdout.strip()
    if not binary or not os.path.isfile(binary):
        fail(f"cannot find the command '{command[0]}'")
    inner = nested_matches(binary, args.collect)
    if inner:
        print(f"count-instructions: warning: '{args.collect}' also matches {len(inner)} lambdas or functions made for a "
              f"matching one ({inner[0][:100]}...); callgrind stops counting inside a match called from a match, "
              "so their instructions are left out: name the outer function from its start, e.g. "
              "'vf::field::ObjectField::mark_occluded(*'", file=sys.stderr)
    with tempfile.TemporaryDirectory() as folder:
        data = os.path.join(folder, "callgrind.out")
        run = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={data}", "--dump-instr=yes",
                              f"--toggle-collect={args.collect}"] + command, capture_output=True, text=True)
        if run.returncode != 0 or not os.path.exists(data):
            fail(f"the command under valgrind exited with {run.returncode}: {run.stderr.strip().splitlines()[-1] if run.stderr.strip() else ''}")
        cost, elsewhere = read_costs(data, os.path.realpath(binary))
    total = sum(cost.values()) + elsewhere
    if total == 0:
        fail(f"no instructions counted: no function matching '{args.collect}' ran")
    # Only the command's own code is disassembled and attributed.
    code = disassemble(binary, list(cost)) if cost else {}
    own = {a: c for a, c in cost.items() if a in code}
    stack = sum(c for a, c in own.items() if "(%rsp" in code[a][1] or "(%rbp" in code[a][1])
    mnemonics = collections.Counter()
    for a, c in own.items():
        mnemonics[code[a][0]] += c
    print(f"instructions: {total:,} ({total - sum(own.values()):,} outside {os.path.basename(binary)})")
    print(f"touching the stack: {stack:,} ({100 * stack / total:.1f}%)")
    print("commonest: " + ", ".join(f"{op} {100 * c / total:.1f}%" for op, c in mnemonics.most_common(8)))
    chains = inline_chains(binary, sorted(own))
    by_line = collections.Counter()
    for a, c in own.items():
        frames = chains.get(a) or [("?", "?")]
        # The innermost frame in the named file, else the innermost outside the system's headers
        # (an intrinsic's line says little), else the innermost.
        ours = [f for f in frames if not f[1].startswith("/usr/") and not any(skip in f[1] for skip in args.skip)]
        pick = next((f for f in frames if args.file and args.file in f[1]), ours[0] if ours else frames[0])
        by_line[(os.path.basename(pick[1]), short_name(pick[0]))] += c
    print(f"\n{'instructions':>14} {'share':>6}  line  function")
    for (line, function), c in by_line.most_common(args.top):
        print(f"{c:>14,} {100 * c / total:5.1f}%  {line}  {function}")


if __name__ == "__main__":
    main()
