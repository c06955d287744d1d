#!/usr/bin/env python3
"""The documentation agrees with the repository: every relative link in README.md and docs/ leads to a file
that exists (and an anchor to one of its headings), no file cites a document the repository does not have
(DESIGN.md lives outside it), the README stays short, and, given the dslam binary, every option a command's
--help lists is documented on that command's page docs/<command>.md.

Usage: docs_check.py SOURCE_DIR [DSLAM_BINARY]. Prints one line per problem and exits 1 when there is one."""
import os
import re
import subprocess
import sys

COMMANDS = ["sim", "kitti-replay", "render-scene", "run", "lidar-check", "serve", "publish", "figures", "study"]
SKIP_DIRS = {".git", "build", "results", "__pycache__"}
TEXT_EXT = {".md", ".h", ".cpp", ".c", ".py", ".sh", ".txt", ".yaml", ".xml", ".cmake", ".idl", ".msg", ""}
README_MAX_LINES = 250


def slug(heading):
    # GitHub's anchors: lower case, punctuation other than '-' and '_' dropped, spaces to '-'.
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(path):
    result = set()
    in_code = False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            in_code = not in_code
        elif not in_code and line.startswith("#"):
            result.add(slug(line.lstrip("#")))
    return result


def markdown_files(root):
    files = [os.path.join(root, "README.md")]
    docs = os.path.join(root, "docs")
    if os.path.isdir(docs):
        files += [os.path.join(docs, f) for f in sorted(os.listdir(docs)) if f.endswith(".md")]
    return [f for f in files if os.path.isfile(f)]


def check_links(root, problems):
    for md in markdown_files(root):
        text = open(md, encoding="utf-8").read()
        text = re.sub(r"```.*?```", "", text, flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"^[a-z]+:", target):
                continue  # http:, mailto:
            path, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(md), path)) if path else md
            rel = os.path.relpath(md, root)
            if not os.path.exists(resolved):
                problems.append(f"{rel}: link to {target}: no such file")
            elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                problems.append(f"{rel}: link to {target}: no heading '#{anchor}' there")


def check_citations(root, problems):
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = [d for d in dirnames if d not in SKIP_DIRS]
        if os.path.relpath(dirpath, root) == os.path.join("tests", "docs"):
            dirnames[:] = [d for d in dirnames if d != "broken"]  # the check's own fixture of what it refuses
        for f in filenames:
            if os.path.splitext(f)[1] not in TEXT_EXT:
                continue
            path = os.path.join(dirpath, f)
            if os.path.abspath(path) == os.path.abspath(__file__):
                continue
            try:
                for n, line in enumerate(open(path, encoding="utf-8"), 1):
                    if "DESIGN.md" in line:
                        problems.append(f"{os.path.relpath(path, root)}:{n}: cites DESIGN.md, which is not in the "
                                        "repository (docs/design.md is)")
            except UnicodeDecodeError:
                pass


def check_readme_length(root, problems):
    n = sum(1 for _ in open(os.path.join(root, "README.md"), encoding="utf-8"))
    if n > README_MAX_LINES:
        problems.append(f"README.md: {n} lines, at most {README_MAX_LINES} (the rest belongs in docs/)")


def check_options(root, binary, problems):
    for command in COMMANDS:
        page = os.path.join(root, "docs", command + ".md")
        if not os.path.isfile(page):
            problems.append(f"docs/{command}.md: missing (dslam {command} has no page)")
            continue
        text = open(page, encoding="utf-8").read()
        help_text = subprocess.run([binary, command, "--help"], capture_output=True, text=True).stdout
        options = set(re.findall(r"^\s+(?:-\w,)?(--[\w-]+)", help_text, flags=re.M)) - {"--help"}
        if not options:
            problems.append(f"dslam {command} --help lists no options")
        for option in sorted(options):
            if not re.search(re.escape(option) + r"(?![\w-])", text):
                problems.append(f"docs/{command}.md: option {option} of dslam {command} is not documented")


def main():
    root = sys.argv[1]
    problems = []
    check_links(root, problems)
    check_citations(root, problems)
    check_readme_length(root, problems)
    if len(sys.argv) > 2:
        check_options(root, sys.argv[2], problems)
    for p in problems:
        print(p)
    if problems:
        return 1
    print("documentation consistent")
    return 0


if __name__ == "__main__":
    sys.exit(main())
