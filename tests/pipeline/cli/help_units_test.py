"""Every option of every `fogpipe` command that takes a physical quantity shows its unit in
`fogpipe COMMAND --help`: in its name (`--duration-s`, `--sample-rate-hz`) or in its help text
(`[s]`, `deg/h`, `in samples`); and its default: `=value`, or the word "default" in its text or
in the command's footer. The rule, which words name a quantity and what counts as a unit, is
written here and nowhere else.

    help_units_test.py FOGPIPE [COMMAND...]   (default: every command of `fogpipe --help`)
"""
import re
import subprocess
import sys

# Words that say an option's value is a physical quantity (or a count of something with a unit).
QUANTITY = re.compile(
    r"\b(rate|time|times|frequency|duration|length|tau|noise|period|latitude|temperature|gap|"
    r"interval|timeout|delay|bias|coefficient|amplitude|memory|budget|size|step|drop|window|"
    r"seconds?|sigma|variance|deviation|tolerance|threshold|ratio|scale)\b",
    re.IGNORECASE)
# A unit in the option's name: its last word(s) after a dash.
NAME_UNIT = re.compile(
    r"-(s|ms|hz|deg|degc|rad|percent|samples|bytes|arcsec|h|deg-h|deg-s|rad-s|deg-sqrt-h|"
    r"deg-h-sqrt-h|deg-h2|ratio|scale|factor|fraction)$")
# A unit in the help text: a unit word, or a placeholder such as F_HZ or TC_S; a text that names
# where the unit comes from ("the recording's unit", "--units") counts too, and so does a
# dimensionless value that says what it is (a fraction, a ratio, a multiplier).
TEXT_UNIT = re.compile(
    r"(?<![\w'])(s|ms|us|ns|Hz|h|deg|deg/h|deg/s|rad/s|rad|degC|arcsec|samples|lines|bytes|"
    r"deg/sqrt\(h\)|deg/h/sqrt\(h\)|deg/h\^2|[KMG]iB|[kMG]B)(?![\w/])"
    r"|%|_(S|HZ|DEG|DEG_H|DEG_S|DEGC)\b|\bunits?\b"
    # dimensionless, and said so
    r"|\b(fraction|dimensionless|ratio|multiplier|factor)\b", re.IGNORECASE)
# Options whose value names a choice or a count of things, not a quantity, though their text
# uses one of the words above; each with why.
NOT_A_QUANTITY = {
    "--noise-id": "names the noise-identification rule",
    "--noise-rule": "names the Kalman q/R rule",
    "--seed": "a random seed",
    "--threads": "a count of threads",
    "--ar-order": "AR model orders, counts",
}
# A value that is a number, or a list of numbers written with placeholders such as T_S:DEG_H.
NUMERIC = re.compile(r"(FLOAT|INT|UINT)\b")
PLACEHOLDERS = re.compile(r"\b[A-Z][A-Z0-9]*(_[A-Z0-9]+)*:[A-Z]")
# CLI11's "TYPE=value" or "TYPE:CHECK in [a - b]=value" after the option's name.
SHOWN_DEFAULT = re.compile(r"^\s*(-\w,)?--[\w-]+ [A-Z]+\S*( in \[[^\]]*\])?=")
OPTION = re.compile(r"^  (-\w,)?(--[\w-]+)(\s+(\S+))?")


def help_text(fogpipe, command):
    return subprocess.run([fogpipe, command, "--help"], capture_output=True, text=True,
                          check=True).stdout


def options(text):
    """(name, whole entry) of every option whose value is a number or a list of numbers,
    continuation lines joined."""
    entries, current = [], None
    for line in text.splitlines():
        m = OPTION.match(line)
        if m:
            current = [m.group(2), line]
            entries.append(current)
        elif current is not None and line.startswith("    ") and line.strip():
            current[1] += " " + line.strip()
        else:
            current = None
    out = []
    for name, entry in entries:
        kind = OPTION.match(entry).group(4) or ""
        if NUMERIC.match(kind) or (kind.startswith("TEXT") and PLACEHOLDERS.search(entry)):
            out.append((name, entry))
    return out


def missing_units_and_defaults(fogpipe, command):
    text = help_text(fogpipe, command)
    # CLI11 prints the footer last, after a blank line; the options block ends otherwise.
    last = text.rstrip().split("\n\n")[-1]
    is_footer = not re.match(r"(Options|Positionals|Subcommands|Usage)", last.lstrip())
    footer_default = is_footer and "default" in last
    bad = []
    for name, entry in options(text):
        if name in NOT_A_QUANTITY or not QUANTITY.search(name.replace("-", " ") + " " + entry):
            continue
        if not (NAME_UNIT.search(name) or TEXT_UNIT.search(entry.split(None, 2)[-1])):
            bad.append(f"no unit: fogpipe {command} {name}: {entry.strip()}")
        if not SHOWN_DEFAULT.search(entry) and "default" not in entry and not footer_default:
            bad.append(f"no default: fogpipe {command} {name}: {entry.strip()}")
    return bad


def main():
    fogpipe = sys.argv[1]
    commands = sys.argv[2:]
    if not commands:
        listing = subprocess.run([fogpipe, "--help"], capture_output=True, text=True).stdout
        commands = re.findall(r"^  (\w+)\s", listing.split("SUBCOMMANDS:")[-1], re.MULTILINE)
    assert commands, "no command found in fogpipe --help"
    # The rule must be able to fail: an option of a quantity without a unit is caught.
    assert QUANTITY.search("Record length") and not TEXT_UNIT.search("Record length")
    bad = [line for command in commands for line in missing_units_and_defaults(fogpipe, command)]
    for line in bad:
        print(line)
    print(f"{len(commands)} commands checked: {' '.join(commands)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
