#!/usr/bin/env python3
"""Unity groups for one target (a library, the benchmarks): which of its sources may be compiled
together as one unity source.

A unity source #includes several .cpp files into one translation unit, so the headers they share
(the standard library, glm, toml++, CLI11, Boost) are compiled once per group instead of once per
file. What each file keeps to itself then meets its neighbours': every file's anonymous namespace
becomes one namespace, and a macro a file defines reaches the files after it. Two file-local
functions of the same name and different parameters would then overload each other without a
compiler error, so a group never holds two files that define the same file-local name; a file that
defines a macro or has its own compile options or definitions is compiled on its own.

The file-local names come from Universal Ctags (Debian's universal-ctags): functions, variables,
types, enumerators and aliases declared in an anonymous namespace or `static` at namespace scope,
and macros.

  unity_groups.py --ctags CTAGS --prefix NAME --max-files N FILE...
      prints one line per group of two or more files: "NAME_<k>|FILE|FILE..."
  unity_groups.py --ctags CTAGS --check GROUPS_FILE --stamp STAMP
      reads the lines printed above and fails, naming the files and the names, when two files of one
      group now share a file-local name or a grouped file now defines a macro (the sources changed
      since CMake grouped them: configure again); on success touches STAMP
"""
import argparse
import os
import re
import subprocess
import sys

LOCAL_KINDS = {"function", "variable", "struct", "class", "enum", "typedef", "union", "enumerator", "prototype"}

# The test and benchmark macros, told to ctags as what they define. GoogleTest's TEST(Suite, Name)
# declares the class Suite_Name_Test (GTEST_TEST_CLASS_NAME_ in gtest-internal.h), unique in the
# program, and defines its TestBody(); Google Benchmark's BENCHMARK(function) defines a static
# registration variable that benchmark.h names uniquely with __COUNTER__ (named here after the
# function). Unexpanded, ctags reads every test as a file-local function named TEST (and every
# registration as one named BENCHMARK), and two test files could never share a group.
TEST_MACROS = [
    *(f"-D{macro}(suite,name)=class suite##_##name##_Test {{}}; void suite##_##name##_Test::TestBody()"
      for macro in ("TEST", "TEST_F", "TEST_P")),
    "-DBENCHMARK(function)=static int function##_registration",
    "-DBENCHMARK_CAPTURE(function,name,...)=static int function##_##name##_registration",
]


def file_locals(ctags, paths):
    """{path: (set of file-local names, set of macro names)} for every path."""
    result = {path: (set(), set()) for path in paths}
    if not paths:
        return result
    out = subprocess.run(
        [ctags, "--fields=+sKZ", "--kinds-C++=+fvcsgtuepd", "-o", "-", "--output-format=u-ctags",
         "--language-force=C++", *TEST_MACROS, *paths],
        capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        parts = line.split("\t")
        if len(parts) < 4 or parts[0].startswith("__anon") or parts[0].startswith("!_TAG"):
            continue
        name, path = parts[0], parts[1]
        if path not in result:
            continue
        kind, fields = None, {}
        for part in parts[3:]:
            key, colon, value = part.partition(":")
            if colon:
                fields[key] = value
            else:
                kind = part
        names, macros = result[path]
        if kind == "macro":
            macros.add(name)
            continue
        if kind not in LOCAL_KINDS:
            continue
        scope_kind, _, scope = fields.get("scope", "").partition(":")
        innermost = scope.split("::")[-1] if scope else ""
        if scope_kind == "namespace" and innermost.startswith("__anon"):
            names.add(name)          # declared in an anonymous namespace
        elif scope_kind == "enum" and "__anon" in scope:
            names.add(name)          # an enumerator of an enum in one
        elif "file" in fields and scope_kind in ("namespace", "") and kind in ("function", "variable", "prototype"):
            names.add(name)          # static at namespace scope
    return result


def make_groups(ctags, prefix, max_files, paths):
    """First fit in the library's order (neighbours share headers): each file joins the first group
    not yet full that defines none of its file-local names."""
    found = file_locals(ctags, paths)
    groups = []                             # [files, names]
    for path in paths:
        names, macros = found[path]
        if macros:
            continue                        # compiled on its own
        for group in groups:
            if len(group[0]) < max_files and not names & group[1]:
                group[0].append(path)
                group[1].update(names)
                break
        else:
            groups.append([[path], set(names)])
    return [files for files, _ in groups if len(files) > 1]


def check(ctags, groups_file, stamp):
    problems = []
    with open(groups_file, encoding="utf-8") as lines:
        for line in lines:
            fields = line.rstrip("\n").split("|")
            if len(fields) < 3:
                continue
            group, paths = fields[0], [path for path in fields[1:] if os.path.exists(path)]
            found = file_locals(ctags, paths)
            seen = {}
            for path in paths:
                names, macros = found[path]
                if macros:
                    problems.append(f"{path} defines the macro(s) {', '.join(sorted(macros))} and sits in unity group {group}")
                for name in sorted(names):
                    if name in seen:
                        problems.append(f"{path} and {seen[name]} both define the file-local name '{name}' and sit in "
                                        f"unity group {group}")
                    else:
                        seen[name] = path
    if problems:
        sys.stderr.write("unity groups: the sources changed since CMake grouped them; configure again "
                         "(cmake -S . -B build) or rename the names:\n  " + "\n  ".join(problems) + "\n")
        return 1
    with open(stamp, "w", encoding="utf-8") as out:
        out.write("checked\n")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ctags", required=True)
    parser.add_argument("--prefix")
    parser.add_argument("--max-files", type=int, default=8)
    parser.add_argument("--check")
    parser.add_argument("--stamp")
    parser.add_argument("files", nargs="*")
    args = parser.parse_args()
    if args.check:
        return check(args.ctags, args.check, args.stamp)
    for index, group in enumerate(make_groups(args.ctags, args.prefix, args.max_files, args.files)):
        print("|".join([f"{args.prefix}_{index}", *group]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
