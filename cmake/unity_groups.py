#!/usr/bin/env python3
"""Unity groups for one target (a library, the benchmarks, the test program): which of its sources
may be compiled together as one unity source.

A unity source #includes several .cpp files into one translation unit, so the headers they share
(the standard library, glm, toml++, CLI11, Boost) are compiled once per group instead of once per
file. What each file keeps to itself then meets its neighbours': every file's anonymous namespace
becomes one namespace, and a macro a file defines reaches the files after it. Two file-local
functions of the same name and different parameters would then overload each other without a
compiler error, so a group never holds two files that define the same file-local name; a file that
defines a macro or has its own compile options or definitions is compiled on its own.

A file-local name also meets every later file of its group that names it: a later file's local
`constexpr int kWidth` shadows an earlier file's file-local `kWidth` (a -Wshadow error), and a
later file's unqualified call `analyse(data, options)` meant for the library's function first finds
an earlier file's file-local `analyse`, and takes it without a word when its parameters fit. The
test program's files share such helper names (kWidth, kHeight, small_display); with
--apart-when-named a group also keeps apart two files when one names, outside comments, strings
and member accesses, a file-local name the other defines. The libraries and the benchmarks are
grouped by the first rule alone.

The file-local names come from Universal Ctags (Debian's universal-ctags): functions, variables,
types, enumerators and aliases declared in an anonymous namespace or `static` at namespace scope,
and macros. The names a file uses come from its own tokens (comments, string and character
literals, numbers and #include lines skipped; `a.name`, `a->name` and `Scope::name` are not
unqualified uses).

  unity_groups.py --ctags CTAGS [--apart-when-named] --prefix NAME --max-files N FILE...
      prints one line per group of two or more files: "NAME_<k>|FILE|FILE..."
  unity_groups.py --ctags CTAGS [--apart-when-named] --check GROUPS_FILE --stamp STAMP
      reads the lines printed above and fails, naming the files and the names, when two files of one
      group now share a file-local name (with --apart-when-named: one names another's) or a grouped
      file now defines a macro (the sources changed since CMake grouped them: configure again); on
      success touches STAMP
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


# One C++ token at a time, for the names a file uses: what is skipped comes first (a raw string
# before the identifier R, a number before a character literal so that 1'000 is one number).
TOKEN = re.compile(r"""
    (?P<skip>//[^\n]*
      | /\*.*?\*/
      | (?:u8|u|U|L)?R"(?P<delimiter>[^()\\\s]{0,16})\(.*?\)(?P=delimiter)"
      | (?:u8|u|U|L)?"(?:\\.|[^"\\\n])*"
      | \.?\d(?:[eEpP][+-]|'(?=\w)|[\w.])*
      | (?:u8|u|U|L)?'(?:\\.|[^'\\\n])+'
      | \#[ \t]*include[^\n]*)
  | (?P<name>[A-Za-z_]\w*)
  | (?P<punctuation>::|->|[^\s\w])
""", re.S | re.X)


def used_names(path):
    """The names a file uses unqualified: its identifiers outside comments, string and character
    literals and #include lines, less those after `.` or `->` (members) and after `Scope::` or
    `Template<...>::` (qualified; a leading `::` still reaches the global namespace's anonymous
    one, so a name after it counts)."""
    with open(path, encoding="utf-8", errors="replace") as source:
        text = source.read()
    names = set()
    previous, before = None, None           # the last two tokens: ("name"|"punctuation", text)
    for match in TOKEN.finditer(text):
        kind = match.lastgroup
        if kind not in ("name", "punctuation"):
            continue                        # a comment, a literal or an #include line
        token = (kind, match.group(kind))
        if kind == "name":
            member = previous is not None and previous[1] in (".", "->")
            qualified = (previous is not None and previous[1] == "::" and before is not None
                         and (before[0] == "name" or before[1] == ">"))
            if not member and not qualified:
                names.add(token[1])
        previous, before = token, previous
    return names


def file_facts(ctags, paths, apart_when_named):
    """{path: (file-local names, macro names, names used)}; the names used only with
    apart_when_named (else empty)."""
    found = file_locals(ctags, paths)
    return {path: (names, macros, used_names(path) if apart_when_named else set())
            for path, (names, macros) in found.items()}


def clashes(one, other):
    """The names that keep two files' facts apart: a file-local name both define, or (the names
    used being present) one file's file-local name the other names."""
    names, _, used = one
    other_names, _, other_used = other
    return (names & other_names) | (names & other_used) | (other_names & used)


def make_groups(ctags, prefix, max_files, paths, apart_when_named=False):
    """First fit in the target's order (neighbours share headers): each file joins the first group
    not yet full whose files it does not clash with (clashes above)."""
    facts = file_facts(ctags, paths, apart_when_named)
    groups = []                             # [files, defined names, used names]
    for path in paths:
        names, macros, used = facts[path]
        if macros:
            continue                        # compiled on its own
        for group in groups:
            if len(group[0]) < max_files and not clashes((names, macros, used), (group[1], set(), group[2])):
                group[0].append(path)
                group[1].update(names)
                group[2].update(used)
                break
        else:
            groups.append([[path], set(names), set(used)])
    return [files for files, _, _ in groups if len(files) > 1]


def check(ctags, groups_file, stamp, apart_when_named=False):
    problems = []
    with open(groups_file, encoding="utf-8") as lines:
        for line in lines:
            fields = line.rstrip("\n").split("|")
            if len(fields) < 3:
                continue
            group, paths = fields[0], [path for path in fields[1:] if os.path.exists(path)]
            facts = file_facts(ctags, paths, apart_when_named)
            seen = {}
            for path in paths:
                names, macros, _ = facts[path]
                if macros:
                    problems.append(f"{path} defines the macro(s) {', '.join(sorted(macros))} and sits in unity group {group}")
                for name in sorted(names):
                    if name in seen:
                        problems.append(f"{path} and {seen[name]} both define the file-local name '{name}' and sit in "
                                        f"unity group {group}")
                    else:
                        seen[name] = path
            for index, path in enumerate(paths):
                for other in paths[index + 1:]:
                    for user, owner in ((path, other), (other, path)):
                        named = sorted((facts[owner][0] & facts[user][2]) - facts[user][0])
                        if named:
                            problems.append(f"{user} names {owner}'s file-local name(s) {', '.join(named)} and both "
                                            f"sit in unity group {group}")
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
    parser.add_argument("--apart-when-named", action="store_true",
                        help="also keep apart two files when one names a file-local name the other defines")
    parser.add_argument("--check")
    parser.add_argument("--stamp")
    parser.add_argument("files", nargs="*")
    args = parser.parse_args()
    if args.check:
        return check(args.ctags, args.check, args.stamp, args.apart_when_named)
    for index, group in enumerate(make_groups(args.ctags, args.prefix, args.max_files, args.files,
                                              args.apart_when_named)):
        print("|".join([f"{args.prefix}_{index}", *group]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
