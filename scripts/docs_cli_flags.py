"""Writes the flag tables of docs/cli.md ("Every command and flag") from the built binary's
own help (`impact <command> -h`), so the reference is the parser's. tests/docs.rs checks that
every flag of every command appears in docs/cli.md. Usage:
    python3 scripts/docs_cli_flags.py target/release/impact > /tmp/flags.md"""
import re, subprocess, sys

exe = sys.argv[1]

def help_of(cmd):
    return subprocess.run([exe, *cmd, "-h"], capture_output=True, text=True, check=True).stdout

def commands(cmd=()):
    text = help_of(list(cmd))
    subs = []
    if "Commands:" in text:
        for line in text.split("Commands:")[1].splitlines()[1:]:
            if not line.startswith("  "):
                break
            name = line.split()[0]
            if name != "help":
                subs.append(name)
    out = [] if not cmd else [tuple(cmd)]
    for s in subs:
        out += commands((*cmd, s))
    return out

def flags(text):
    """(flag, value, help) for every option and argument of a help text."""
    rows, cur = [], None
    section = None
    for line in text.splitlines():
        if line in ("Options:", "Arguments:"):
            section = line
            continue
        if section is None or not line.strip():
            continue
        m = re.match(r"^  (?:-\w, )?\s*(--[\w-]+)(?: <([^>]+)>(\.\.\.)?)?\s*(.*)$", line)
        a = re.match(r"^  (\[?<?[A-Z_]+>?\]?(?:\.\.\.)?)\s+(.*)$", line)
        if m and not line.startswith("          "):
            cur = [m.group(1), m.group(2) or "", m.group(4)]
            rows.append(cur)
        elif a and section == "Arguments:" and not line.startswith("          "):
            cur = [a.group(1), "", a.group(2)]
            rows.append(cur)
        elif cur is not None:
            cur[2] = (cur[2] + " " + line.strip()).strip()
    return [r for r in rows if r[0] not in ("--help", "--version")]

def cell(text):
    return text.replace("|", "\\|")

cmds = commands()
tables = {c: flags(help_of(list(c))) for c in cmds}
# flags shared by every command that takes a scene and method options
shared = None
for c, rows in tables.items():
    if any(r[0] == "--courant" for r in rows):
        names = {r[0] for r in rows}
        shared = names if shared is None else shared & names
shared = shared or set()
print("## Every command and flag\n")
print("Written from the parser's own help by `python3 scripts/docs_cli_flags.py "
      "target/release/impact`; `impact <command> --help` prints the same with more detail.\n")
users = [" ".join(c) for c, rows in tables.items() if any(r[0] == "--courant" for r in rows)]
print("### Scene and method flags\n")
print("Taken by " + ", ".join(f"`impact {u}`" for u in users) +
      ": each overrides the scene file's value (docs/scenes.md).\n")
print("| flag | meaning |\n|---|---|")
first = next(c for c, rows in tables.items() if any(r[0] == "--courant" for r in rows))
for f, v, h in tables[first]:
    if f in shared:
        print(f"| `{f}{' <' + v + '>' if v else ''}` | {cell(h)} |")
print()
for c, rows in tables.items():
    about = help_of(list(c)).splitlines()[0]
    print(f"### `impact {' '.join(c)}`\n")
    print(cell(about) + "\n")
    own = [r for r in rows if r[0] not in shared]
    if not own:
        print("No flags of its own.\n")
        continue
    if any(r[0] in shared for r in rows):
        print("Also the scene and method flags above.\n")
    print("| flag or argument | meaning |\n|---|---|")
    for f, v, h in own:
        print(f"| `{f}{' <' + v + '>' if v else ''}` | {cell(h)} |")
    print()
