#!/usr/bin/env python3
"""Worst-case stack of a Cortex-M image, through its call graph.

What it computes: the largest sum of stack frames along any call path from
the reset entry (Reset_Handler, which calls main), plus, for every level of
exceptions that can preempt that path at its deepest point, the deepest
handler path and the hardware exception frame. Prints

    stack_worst=N path=Reset_Handler>main>...>leaf handlers=M exception_frame=F total=T ...

and writes that line, then the details, to --out.

Where the figures come from:
  * our code: the .ci files gcc writes with -fcallgraph-info=su (VCG text,
    one per object, next to it): each function's frame and its calls;
  * which functions the image holds, and from which object: its symbol
    table (objdump -t) and its linker map (-Wl,-Map), so the .ci files of
    other images in the same build directory do not count;
  * the image's disassembly (objdump -d): direct calls are taken from it as
    well (a call the compiler adds after writing the .ci, or to a weak
    function another object replaced, still counts), and the frames of code
    without a .ci (libgcc, newlib): every push, vpush, `sub sp, #N` and
    pre-decrementing store, summed over the whole function (a bound). The
    same reading of the functions that have a .ci must give at least gcc's
    figure, which checks it;
  * indirect calls: a checked-in table (--indirect, stack_indirect.txt)
    naming, for each calling function, the functions it may call.

Fails (exit status 1, every reason printed) on: recursion (the cycle is
named), a dynamic frame (VLA, alloca), an indirect call from a function the
table does not list, a listed caller with none of its targets in the image,
a function of the image that no analysed path reaches (its address is taken
where the table does not say), an object of the build directory without a
.ci, a disassembly it cannot bound. With --check, also when the total
exceeds --limit; with --report-only, never (it still prints the reasons).

Assumptions:
  * a call adds nothing beyond the callee's frame (bl keeps the return
    address in lr; a function's frame includes the registers it pushes);
  * a tail call is counted as if the caller's frame stayed (a bound);
  * exception levels: NMI, HardFault, and all other exceptions of the
    vector table at one priority (the firmware sets none: all stay at the
    reset priority 0, so none preempts another). Each level can preempt the
    one below; each entry stacks the hardware frame (--exception-frame: 32
    bytes, 104 with the FPU context) plus 4 bytes of alignment padding.

Without an image (--ci FILE... with --entry/--handler), the given .ci files
are the whole program: used by the checker's own tests.

Standard library only.
"""
import argparse
import bisect
import os
import re
import subprocess
import sys

INDIRECT = "__indirect_call"
ALIGN_PAD = 4  # the core aligns the exception frame to 8 bytes (CCR.STKALIGN)
CONDS = {"eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc",
         "hi", "ls", "ge", "lt", "gt", "le", "al"}


class Function:
    def __init__(self, name, obj, addr=None, size=0, is_global=True):
        self.name = name
        self.obj = obj            # object (map spelling) or .ci path
        self.addr = addr
        self.size = size
        self.is_global = is_global
        self.frame = None         # bytes
        self.qualifier = ""       # .ci: static, dynamic, dynamic,bounded
        self.source = ""          # "ci" or "disassembly"
        self.calls = set()
        self.indirect = False
        self.dynamic_sp = False   # disassembly: sp lowered by a register
        self.bound = 0            # disassembly: bytes of stack it lowers
        self.aliases = [name]     # symbols at the same address
        self.indirect_targets = []

    def __repr__(self):
        return self.name


class Failure(Exception):
    pass


# --- .ci files (VCG) --------------------------------------------------------

NODE_RE = re.compile(r'node: \{ title: "([^"]*)" label: "([^"]*)"')
EDGE_RE = re.compile(r'edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"')
FRAME_RE = re.compile(r"\\n(\d+) bytes \(([^)]*)\)$")


def short_name(title):
    """'/path/file.c:name' (a unit-local function) or 'name' -> 'name'."""
    return title.rsplit(":", 1)[-1]


def parse_ci(path):
    """Returns ({title: (frame, qualifier)} of the functions defined here,
    {title: [callee titles]})."""
    defined, edges = {}, {}
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = NODE_RE.match(line)
            if m:
                fm = FRAME_RE.search(m.group(2))
                if fm:
                    defined[m.group(1)] = (int(fm.group(1)), fm.group(2))
                continue
            m = EDGE_RE.match(line)
            if m:
                edges.setdefault(m.group(1), []).append(m.group(2))
    return defined, edges


# --- the image: symbols, map, vectors, disassembly --------------------------

def run(cmd):
    try:
        return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise Failure("cannot run %s: %s" % (" ".join(cmd), e))


SYM_RE = re.compile(r"^([0-9a-f]{8}) (.{7}) (\S+)\t([0-9a-f]{8}) (.+)$")


def image_functions(objdump, image, map_path):
    """Function symbols, one per address (aliases kept), each with its
    object from the map; a size of 0 (an assembly function without .size)
    runs to the next function or the end of its input section."""
    by_addr, outputs = {}, set()
    for line in run([objdump, "-t", image]).splitlines():
        m = SYM_RE.match(line)
        if not m or "F" not in m.group(2):
            continue
        outputs.add(m.group(3))
        flags, addr = m.group(2), int(m.group(1), 16) & ~1
        name = re.sub(r"^\.(hidden|protected|internal) ", "", m.group(5))
        f = by_addr.get(addr)
        if f is None:
            f = by_addr[addr] = Function(name, None, addr, int(m.group(4), 16),
                                         flags[0] == "g" or flags[1] == "w")
        else:
            f.aliases.append(name)
            f.size = max(f.size, int(m.group(4), 16))
    funcs = sorted(by_addr.values(), key=lambda f: f.addr)
    sections = map_sections(map_path, outputs)
    starts = [s[0] for s in sections]
    for k, f in enumerate(funcs):
        i = bisect.bisect_right(starts, f.addr) - 1
        if i < 0 or f.addr >= sections[i][0] + sections[i][1]:
            raise Failure("%s at 0x%x: in no input section of the map" % (f.name, f.addr))
        f.obj = sections[i][2]
        if f.size == 0:
            end = sections[i][0] + sections[i][1]
            if k + 1 < len(funcs):
                end = min(end, funcs[k + 1].addr)
            f.size = end - f.addr
    return funcs


def map_sections(path, outputs):
    """Input sections placed in the given output sections of the image:
    sorted [(addr, size, object)]."""
    text = open(path, encoding="utf-8", errors="replace").read()
    start = text.find("Linker script and memory map")
    if start < 0:
        raise Failure("%s: not a GNU ld map file" % path)
    # A long section name puts address, size and object on the next line.
    text = re.sub(r"\n( ?\.\S+)\n\s+0x", r"\n\1 0x", text[start:])
    out, current = [], None
    for line in text.splitlines():
        m = re.match(r"^(\.\S+)\s+0x[0-9a-f]+", line)
        if m:
            current = m.group(1)
            continue
        m = re.match(r"^ \.\S+\s+0x([0-9a-f]+)\s+0x([0-9a-f]+) (\S.*)$", line)
        if m and current in outputs and int(m.group(2), 16):
            out.append((int(m.group(1), 16), int(m.group(2), 16), m.group(3).strip()))
    return sorted(out)


def vector_table(objdump, image):
    """Handler addresses by vector number (0: initial SP)."""
    words = []
    for line in run([objdump, "-s", "-j", ".isr_vector", image]).splitlines():
        m = re.match(r"^ [0-9a-f]+ ((?:[0-9a-f]{8} ?){1,4})", line)
        if m:
            for w in m.group(1).split():
                words.append(int.from_bytes(bytes.fromhex(w), "little"))
    return words


def reg_count(operands):
    """Registers in '{r4, r5, lr}' or '{d8-d15}', weighted by size."""
    inner = operands[operands.find("{") + 1:operands.find("}")]
    total = 0
    for part in inner.split(","):
        part = part.strip()
        width = 8 if part.startswith("d") else 4
        if "-" in part:
            a, b = part.split("-")
            total += width * (int(b[1:]) - int(a[1:]) + 1)
        elif part:
            total += width
    return total


INSN_RE = re.compile(r"^\s*([0-9a-f]+):\t(\S+)(?:\t(.*))?$")


def scan_disassembly(objdump, image, funcs):
    """Per function: direct callee addresses, indirect calls, stack bound."""
    starts = [f.addr for f in funcs]

    def owner(addr):
        i = bisect.bisect_right(starts, addr) - 1
        if i >= 0 and addr < funcs[i].addr + max(funcs[i].size, 1):
            return funcs[i]
        return None

    switch = None  # the function whose jump table follows, and its entries seen
    for line in run([objdump, "-d", "--no-show-raw-insn", image]).splitlines():
        m = INSN_RE.match(line)
        f = owner(int(m.group(1), 16)) if m else None
        if f is None:
            continue
        mnem, ops = m.group(2), (m.group(3) or "").split(";")[0].split("@")[0].strip()
        base = mnem if mnem.startswith(".") else mnem.split(".")[0]
        # A switch: 'ldr pc, [rX, rY, lsl #2]' and a table of addresses in
        # the same function; any other entry is an indirect jump.
        if switch and switch[0] is f and base in (".word", "nop"):
            if base == ".word":
                switch[1] += 1
                t = int(ops, 16) & ~1
                f.indirect |= not f.addr <= t < f.addr + f.size
            continue
        if switch:
            switch[0].indirect |= switch[1] == 0
            switch = None
        if base.startswith("."):
            continue
        target = re.match(r"^([0-9a-f]+) <", ops)
        # Calls and branches ('bl' + condition inside an IT block, too).
        if base == "bl" or (base[:2] == "bl" and base[2:] in CONDS):
            if target:
                f.calls.add(int(target.group(1), 16))
        elif base.startswith("blx") or (base.startswith("bx") and not ops.startswith("lr")):
            f.indirect = True
        elif base in ("b", "cbz", "cbnz") or (base[:1] == "b" and base[1:] in CONDS):
            if target:
                t = int(target.group(1), 16)
                if not f.addr <= t < f.addr + f.size:
                    f.calls.add(t)  # a tail call
        elif ops.startswith("pc,") and base == "ldr" and re.match(r"^pc, \[\w+, \w+", ops):
            switch = [f, 0]
        elif ops.startswith("pc,") and base in ("mov", "ldr") and "[sp]" not in ops:
            f.indirect = True
        # Stack lowered: push, vpush, stmdb sp!, sub sp, str [sp, #-N]!.
        b = f.bound
        if base in ("push", "vpush") or (base in ("stmdb", "vstmdb") and ops.startswith("sp!")):
            b += reg_count(ops)
        elif base in ("sub", "subw") and re.match(r"^sp, (sp, )?#\d+$", ops):
            b += int(ops.rsplit("#", 1)[1])
        elif base in ("sub", "subw") and ops.startswith("sp,"):
            f.dynamic_sp = True
        else:
            pre = re.search(r"\[sp, #-(\d+)\]!$", ops)
            if pre and base.startswith("str"):
                b += int(pre.group(1))
        f.bound = b
    # Call targets as functions.
    for f in funcs:
        f.calls = {owner(a) for a in f.calls} - {None}


def ci_path(obj, link_dir, build_dir):
    """The .ci of an object as the map names it, 'dir/x.c.obj' (next to it)
    or 'dir/libN.a(x.c.obj)' (CMake keeps a library's objects under
    dir/CMakeFiles/N.dir/); paths relative to link_dir. None for an object
    from outside build_dir (a system library); '' when none is found."""
    m = re.match(r"^(.*)\((.*)\)$", obj)
    path = os.path.normpath(os.path.join(link_dir, m.group(1) if m else obj))
    if not path.startswith(build_dir + os.sep):
        return None
    if not m:
        ci = os.path.splitext(path)[0] + ".ci"
        return ci if os.path.exists(ci) else ""
    lib = os.path.splitext(os.path.basename(path))[0]
    lib_dir = os.path.join(os.path.dirname(path), "CMakeFiles",
                           (lib[3:] if lib.startswith("lib") else lib) + ".dir")
    want = os.path.splitext(m.group(2))[0] + ".ci"
    found = [os.path.join(root, want) for root, _, files in os.walk(lib_dir) if want in files]
    return found[0] if len(found) == 1 else ""


# --- the call graph ---------------------------------------------------------

def names(funcs):
    by_name = {}
    for f in funcs:
        for n in f.aliases:
            by_name.setdefault(n, []).append(f)
    return by_name


def attach_ci(funcs, ci_of, errors, disassembled=True):
    """Frames and calls from the .ci files; functions without one keep the
    disassembly's bound. Where both exist, the disassembly's bound must not
    be smaller (else its reading of the code without .ci cannot be trusted)."""
    by_name = names(funcs)
    parsed = {}
    for f in funcs:
        ci = ci_of.get(f.obj)
        if ci and ci not in parsed:
            parsed[ci] = parse_ci(ci)
        defined, edges = parsed.get(ci, ({}, {}))
        title = next((t for t in defined if short_name(t) in f.aliases), None)
        if title is None:
            f.frame, f.source = f.bound, "disassembly"
            if f.dynamic_sp:
                errors.append("%s: the stack pointer is lowered by a register value "
                              "(no bound)" % f.name)
            continue
        f.frame, f.qualifier = defined[title]
        f.source = "ci"
        if disassembled and f.bound < f.frame:
            errors.append("%s: the disassembly shows %d bytes of stack, gcc %d: "
                          "stack_graph.py misreads an instruction" % (f.name, f.bound, f.frame))
        if f.qualifier != "static":
            errors.append("%s: %s frame (%s): no VLA or alloca allowed"
                          % (f.name, f.qualifier, f.obj))
        for t in edges.get(title, []):
            if t == INDIRECT:
                f.indirect = True
                continue
            same_unit = [g for g in by_name.get(short_name(t), []) if g.obj == f.obj]
            if ":" in t and same_unit:
                f.calls.update(same_unit)
            else:
                f.calls.update([g for g in by_name.get(short_name(t), []) if g.is_global]
                               or same_unit)


def read_indirect(path):
    table = {}
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            caller, sep, targets = line.partition(":")
            if not sep or not caller.strip() or not targets.split():
                raise Failure("%s:%d: expected 'caller: target...'" % (path, n))
            table.setdefault(caller.strip(), []).extend(targets.split())
    return table


def resolve_indirect(funcs, table, table_path, errors):
    by_name = names(funcs)
    for f in funcs:
        if not f.indirect:
            continue
        listed = [t for n in f.aliases for t in table.get(n, [])]
        if not listed:
            errors.append("%s (%s) makes an indirect call and is not in %s: add "
                          "'%s: <possible targets>'" % (f.name, f.obj, table_path, f.name))
            continue
        targets = [g for t in listed for g in by_name.get(t, [])]
        if not targets:
            errors.append("%s: none of its indirect targets in %s (%s) is in the image"
                          % (f.name, table_path, " ".join(listed)))
        f.calls.update(targets)
        f.indirect_targets = sorted({g.name for g in targets})


def find_cycle(roots):
    """A call cycle reachable from roots, as a list of functions, or None."""
    state = {}
    stack = []

    def visit(f):
        state[f] = 1
        stack.append(f)
        for g in sorted(f.calls, key=lambda x: x.name):
            if state.get(g) == 1:
                return stack[stack.index(g):] + [g]
            if g not in state:
                cycle = visit(g)
                if cycle:
                    return cycle
        stack.pop()
        state[f] = 2
        return None

    for r in roots:
        if r not in state:
            cycle = visit(r)
            if cycle:
                return cycle
    return None


def deepest(f, memo):
    """(bytes, path) of the deepest path from f (the graph has no cycle)."""
    if f not in memo:
        best = (0, [])
        for g in sorted(f.calls, key=lambda x: (x.name, x.addr or 0)):
            best = max(best, deepest(g, memo), key=lambda x: x[0])
        memo[f] = (f.frame + best[0], [f] + best[1])
    return memo[f]


def reached(roots):
    seen, todo = set(), list(roots)
    while todo:
        f = todo.pop()
        if f not in seen:
            seen.add(f)
            todo.extend(f.calls)
    return seen


def describe(path):
    return " > ".join("%s %d%s" % (f.name, f.frame, "" if f.source == "ci" else " (disassembly)")
                      for f in path)


# --- main -------------------------------------------------------------------

def load_image(a, errors):
    funcs = image_functions(a.objdump, a.image, a.map)
    scan_disassembly(a.objdump, a.image, funcs)
    build_dir = os.path.realpath(a.build_dir)
    link_dir = os.path.realpath(a.link_dir)
    ci_of, missing = {}, []
    for obj in sorted({f.obj for f in funcs}):
        ci = ci_path(obj, link_dir, build_dir)
        if ci == "":
            missing.append(obj)
        elif ci is not None:  # None: a system library, frames from the disassembly
            ci_of[obj] = ci
    if missing:
        errors.append("no .ci for %d objects of the build (%s): build with -fcallgraph-info=su "
                      "(cmake/arm-none-eabi.cmake; configure a fresh build directory)"
                      % (len(missing), ", ".join(missing)))
    attach_ci(funcs, ci_of, errors)
    by_addr = {f.addr: f for f in funcs}
    vectors = vector_table(a.objdump, a.image)
    if len(vectors) < 2 or (vectors[1] & ~1) not in by_addr:
        raise Failure("%s: no reset vector in .isr_vector" % a.image)
    entry = by_addr[vectors[1] & ~1]
    levels = {}
    for n, v in enumerate(vectors[2:], 2):
        if v:
            if (v & ~1) not in by_addr:
                raise Failure("vector %d (0x%x) is no function of the image" % (n, v))
            name = {2: "NMI", 3: "HardFault"}.get(n, "configurable")
            levels.setdefault(name, set()).add(by_addr[v & ~1])
    return funcs, entry, levels


def load_fixture(a, errors):
    funcs = {}
    for ci in a.ci:
        defined, _ = parse_ci(ci)
        for t in defined:
            funcs[(ci, t)] = Function(short_name(t), ci, is_global=":" not in t)
    funcs = list(funcs.values())
    attach_ci(funcs, {ci: ci for ci in a.ci}, errors, disassembled=False)
    by_name = {f.name: f for f in funcs}
    for n in [a.entry] + a.handler:
        if n not in by_name:
            raise Failure("%s: not defined in the .ci files" % n)
    levels = {"configurable": {by_name[n] for n in a.handler}} if a.handler else {}
    return funcs, by_name[a.entry], levels


def analyse(a):
    """Returns (result line, detail lines, total bytes)."""
    errors = []
    funcs, entry, levels = load_image(a, errors) if not a.ci else load_fixture(a, errors)
    resolve_indirect(funcs, read_indirect(a.indirect), a.indirect, errors)
    roots = [entry] + sorted({h for hs in levels.values() for h in hs}, key=lambda f: f.name)
    cycle = find_cycle(roots)
    if cycle:
        errors.append("recursion: " + ">".join(f.name for f in cycle))
    unreached = sorted({f.name for f in set(funcs) - reached(roots)})
    if unreached:
        errors.append("in the image but reached by no analysed call (called through a "
                      "pointer %s does not list?): %s" % (a.indirect, " ".join(unreached)))
    if errors:
        raise Failure("\n".join(errors))

    memo = {}
    worst, path = deepest(entry, memo)
    frame = a.exception_frame + ALIGN_PAD
    handler_paths = []
    for level in ("configurable", "HardFault", "NMI"):
        if level in levels:
            handler_paths.append((level, max((deepest(h, memo) for h in levels[level]),
                                             key=lambda x: (x[0], x[1][0].name))))
    handler_sum = sum(n for _, (n, _) in handler_paths)
    frames = frame * len(handler_paths)
    total = worst + handler_sum + frames
    line = ("stack_worst=%d path=%s handlers=%d exception_frame=%d total=%d limit=%d "
            "handler_paths=%s" % (worst, ">".join(f.name for f in path), handler_sum, frames,
                                  total, a.limit,
                                  ",".join(">".join(f.name for f in hp) for _, (_, hp)
                                           in handler_paths)))
    details = ["# main path (bytes per frame): " + describe(path)]
    for level, (n, hp) in handler_paths:
        details.append("# level %s: %d + exception frame %d (%d + %d alignment): %s"
                       % (level, n, frame, a.exception_frame, ALIGN_PAD, describe(hp)))
    from_dis = sorted({"%s %d" % (f.name, f.frame) for f in funcs if f.source == "disassembly"})
    details.append("# frames from the disassembly (no .ci): " + (", ".join(from_dis) or "none"))
    for f in sorted(funcs, key=lambda f: f.name):
        if f.indirect:
            details.append("# indirect calls of %s: %s" % (f.name, " ".join(f.indirect_targets)))
    return line, details, total


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--image", help="the linked ELF")
    p.add_argument("--map", help="its linker map")
    p.add_argument("--build-dir", help="the build directory (objects and .ci files)")
    p.add_argument("--link-dir", help="the directory the image was linked in (map paths "
                   "are relative to it); default: --build-dir")
    p.add_argument("--objdump", default="arm-none-eabi-objdump")
    p.add_argument("--ci", nargs="+", help="no image: these .ci files are the program")
    p.add_argument("--entry", default="Reset_Handler", help="with --ci: the entry")
    p.add_argument("--handler", action="append", default=[], help="with --ci: a handler")
    p.add_argument("--indirect", required=True, help="the indirect-call table")
    p.add_argument("--exception-frame", type=int, default=32,
                   help="hardware exception frame: 32, or 104 with the FPU context")
    p.add_argument("--out", help="write the result line and the details here")
    p.add_argument("--check", action="store_true", help="fail when total > --limit")
    p.add_argument("--limit", type=int, default=4096)
    p.add_argument("--report-only", action="store_true",
                   help="exit 0 whatever is found (a build step that only reports)")
    a = p.parse_args()
    if not a.ci and not (a.image and a.map and a.build_dir):
        p.error("give --image, --map and --build-dir, or --ci")
    a.link_dir = a.link_dir or a.build_dir
    try:
        line, details, total = analyse(a)
    except Failure as e:
        msgs = ["stack_graph: error: " + m for m in str(e).split("\n")]
        line, details = msgs[0], msgs[1:]
        print("\n".join(msgs), file=sys.stderr)
        failed = True
    else:
        print(line)
        failed = a.check and total > a.limit
        if failed:
            print("stack_graph: error: worst-case stack %d B > limit %d B" % (total, a.limit),
                  file=sys.stderr)
    if a.out:
        with open(a.out, "w", encoding="utf-8") as out:
            out.write("\n".join([line] + details) + "\n")
    return 1 if failed and not a.report_only else 0


if __name__ == "__main__":
    sys.exit(main())
