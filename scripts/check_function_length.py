#!/usr/bin/python3
"""Holds every C++ function in the given folders to a maximum length, so that a long procedure is
split into named steps before it is merged.

A function's length is counted from the first line of its declaration to its closing brace; the
lambdas and local classes inside it count as part of it. Comments, string, character and raw string
literals and preprocessor lines are blanked out before the braces are matched, so a brace in any
of them does not count. A lambda in a namespace-scope initializer (an option table) is a function
of its own.

Usage: check_function_length.py [--max-lines N] FOLDER_OR_FILE...   (*.h, *.hpp, *.cpp, *.cc)
       check_function_length.py --self-test
Prints FILE:LINE: NAME is L lines (limit N) for every longer function; exit 1 if there is any.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc")


def blank(text):
    """The text with every character other than a newline replaced by a space."""
    return re.sub(r"[^\n]", " ", text)


def strip_code(src):
    """`src` with comments, literals and preprocessor lines blanked; line numbers are kept."""
    out = []
    i, n = 0, len(src)
    line_start = True  # only whitespace since the last newline
    while i < n:
        c = src[i]
        if c == "\n":
            out.append(c)
            line_start = True
            i += 1
            continue
        if line_start and c == "#":
            # A preprocessor directive, with its backslash continuations.
            j = i
            while j < n and src[j] != "\n":
                j = j + 2 if src[j] == "\\" and j + 1 < n else j + 1
            out.append(blank(src[i:j]))
            i = j
            continue
        if not c.isspace():
            line_start = False
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(blank(src[i:j]))
            i = j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(blank(src[i:j]))
            i = j
        elif c == '"' and re.search(r"(?<![A-Za-z0-9_])(?:u8|u|U|L)?R$", src[max(0, i - 3):i]):
            m = re.match(r'"([^()\\\s]{0,16})\(', src[i:])
            end = src.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append('"' + blank(src[i + 1:j - 1]) + '"')
            i = j
        elif c == '"' or (c == "'" and not digit_separator(src, i)):
            j = i + 1
            while j < n and src[j] != c and src[j] != "\n":
                j += 2 if src[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + blank(src[i + 1:j - 1]) + c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def digit_separator(src, i):
    """Whether the quote at src[i] separates digits (1'000'000) rather than opening a literal."""
    j = i
    while j > 0 and (src[j - 1].isalnum() or src[j - 1] in "_'."):
        j -= 1
    return j < i and src[j].isdigit()


def strip_templates(head):
    """`head` without a leading template<...> parameter list."""
    m = re.match(r"\s*template\s*<", head)
    if not m:
        return head
    depth, k = 1, m.end()
    while k < len(head) and depth > 0:
        depth += {"<": 1, ">": -1}.get(head[k], 0)
        k += 1
    return strip_templates(head[k:])


def top_level(head):
    """`head` with everything inside parentheses, brackets and braces removed."""
    out, depth = [], 0
    for c in head:
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif depth == 0:
            out.append(c)
    return "".join(out)


QUALIFIERS = r"(\s*(const|volatile|noexcept(\s*\([^()]*\))?|override|final|mutable|&&?|" \
             r"->\s*[\w:<>,\s*&]+))*\s*$"


def classify(head):
    """What a '{' opens at namespace or class scope, from the text before it: 'function',
    'member-init' (a brace-initialised member in a constructor's initialiser list), 'scope'
    (namespace, class, enum, extern "C") or 'initializer'."""
    head = re.sub(r"^\s*((public|private|protected)\s*:(?!:)\s*)+", "", head)
    head = strip_templates(head)
    flat = top_level(head)
    if re.match(r"\s*(inline\s+)?(namespace|class|struct|union|enum)\b", head) or \
            re.match(r'\s*extern\s*""\s*$', head):
        return "scope"
    if "=" in flat.replace("==", "") and "operator" not in flat:
        after = head[head.index("=") + 1:] if "=" in head else ""
        return "function" if after.lstrip().startswith("[") else "initializer"
    if re.search(r"\)" + QUALIFIERS, head) and "(" in head:
        return "function"
    if re.search(r"\)\s*(noexcept\s*)?:(?!:)", head) and not head.rstrip().endswith(")"):
        return "member-init"
    return "initializer"


def function_name(head):
    """The qualified name before the parameter list, or the head's end."""
    lam = re.search(r"([\w:]+)\s*=\s*(\[[^\]]*\]|$)", head)
    if lam and lam.group(2):
        return lam.group(1) + " (lambda)"
    m = re.search(r"((?:[\w~]+\s*::\s*)*(?:operator\s*\S+?|[\w~]+))\s*\(", head)
    return (m.group(1) if m else head.strip()[-60:]).replace(" ", "")


def functions(src):
    """(name, first line, last line) of every function outside any other function's body."""
    code = strip_code(src)
    found = []
    stack = []  # each open scope: (kind, first line, name)
    head, head_line = "", None  # the text since the last ';', '{' or '}' at this scope
    depth = 0  # braces open inside the innermost function's body
    line = 1
    for c in code:
        if c == "\n":
            line += 1
        kind = stack[-1][0] if stack else "scope"
        if kind == "function":
            if c == "{":
                depth += 1
            elif c == "}" and depth > 0:
                depth -= 1
            elif c == "}":
                _, start, name = stack.pop()
                found.append((name, start, line))
                head, head_line = "", None
            continue
        if c == "{":
            what = classify(head)
            if kind == "initializer" and what != "function":
                # Inside a table at namespace scope only a lambda body is a function.
                what = "function" if re.search(r"[)\]]" + QUALIFIERS, head) else "initializer"
            stack.append((what, head_line if head_line is not None else line,
                          function_name(head)))
            if what != "member-init":
                head, head_line = "", None
        elif c == "}":
            closed = stack.pop()[0] if stack else "scope"
            if closed != "member-init":
                head, head_line = "", None
        elif c == ";" or (c == "," and kind == "initializer"):
            head, head_line = "", None
        else:
            if head_line is None and not c.isspace():
                head_line = line
            head += c
    return found


def source_files(paths):
    for path in paths:
        if os.path.isfile(path):
            yield path
            continue
        for folder, dirs, files in os.walk(path):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(SOURCE_SUFFIXES):
                    yield os.path.join(folder, name)


def long_functions(paths, max_lines):
    """(file, first line, name, length) of every function longer than max_lines."""
    out = []
    for path in source_files(paths):
        with open(path, encoding="utf-8", errors="replace") as f:
            src = f.read()
        for name, first, last in functions(src):
            if last - first + 1 > max_lines:
                out.append((path, first, name, last - first + 1))
    return out


# A file of the functions the check must measure right: braces in comments, strings, raw strings
# and character literals, a digit separator, a lambda, a constructor's brace-initialised member
# and a class; Long() is 81 lines from its declaration to its brace, the others are short.
SELF_TEST_SOURCE = r'''#include <string>
#define OPEN {
namespace demo {
struct Point { int x{0}; int y = 1'000; };
class Widget {
 public:
  Widget() : a_{1}, b_(2) {
    a_ += '{';
  }
  int Get() const { return a_; }
 private:
  int a_, b_;
};
int Short(int v) {
  const char* text = "}}}{";  // }}}
  /* { */ return v + text[0];
}
auto kTable = [](int v) { return v; };
int Long(int v)
{
  auto twice = [&](int w) {
    return 2 * w;
  };
  const char* raw = R"x(}})x";
@BODY@  return twice(v) + raw[0] + '}';
}
int After() { return 0; }
}  // namespace demo
'''


def self_test():
    """Runs the check on SELF_TEST_SOURCE: it must name Long() alone, at 81 lines, and exit 1;
    with one line fewer it must pass."""
    failures = []
    for body_lines, expect in ((73, [("demo/long.cpp", 19, "Long", 81)]), (72, [])):
        with tempfile.TemporaryDirectory() as folder:
            os.mkdir(os.path.join(folder, "demo"))
            with open(os.path.join(folder, "demo", "long.cpp"), "w") as f:
                f.write(SELF_TEST_SOURCE.replace("@BODY@", "  v += 1;\n" * body_lines))
            got = [(os.path.relpath(p, folder), first, name, n)
                   for p, first, name, n in long_functions([os.path.join(folder, "demo")], 80)]
            # The command itself, as ctest runs it: its exit code and the line naming the function.
            run = subprocess.run([sys.executable, os.path.abspath(__file__), "--max-lines", "80",
                                  os.path.join(folder, "demo")], capture_output=True, text=True)
        if got != expect:
            failures.append(f"with {body_lines} body lines: expected {expect}, got {got}")
        if run.returncode != (1 if expect else 0) or \
                ("long.cpp:19: Long is 81 lines (limit 80)" in run.stdout) != bool(expect):
            failures.append(f"with {body_lines} body lines: exit {run.returncode}, {run.stdout!r}")
    names = sorted(name for name, _, _ in functions(SELF_TEST_SOURCE.replace("@BODY@", "")))
    if names != ["After", "Get", "Long", "Short", "Widget", "kTable (lambda)"]:
        failures.append(f"functions found: {names}")
    for failure in failures:
        print("self-test FAILED:", failure)
    if not failures:
        print("self-test passed: an 81-line function is reported, an 80-line one is not")
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="*", help="folders (searched recursively) or files")
    parser.add_argument("--max-lines", type=int, default=80)
    parser.add_argument("--self-test", action="store_true")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if not args.paths:
        parser.error("give at least one folder or file")
    missing = [p for p in args.paths if not os.path.exists(p)]
    if missing:
        parser.error("no such folder or file: " + ", ".join(missing))
    offenders = long_functions(args.paths, args.max_lines)
    for path, first, name, n in offenders:
        print(f"{path}:{first}: {name} is {n} lines (limit {args.max_lines})")
    files = sum(1 for _ in source_files(args.paths))
    print(f"{len(offenders)} function(s) longer than {args.max_lines} lines in {files} files")
    return 1 if offenders else 0


if __name__ == "__main__":
    sys.exit(main())
