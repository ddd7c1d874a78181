#!/usr/bin/python3
"""The house rules, checked on the source tree (standard library only, no network).

    /usr/bin/python3 scripts/check-house.py [--verbose] [--root DIR]

Rules (docs/reference/testing.md):
  function-length  a C++ function body outside tests/, fuzz/ and build*/ spans more than 80 lines
                   and is not in FUNCTION_ALLOWLIST (numerical kernels that read better whole);
                   the functions under "to split" are printed as warnings only
  twin-overlap     a source file and its dimension twin (foo.cpp and foo3d.cpp) share more runs
                   of 6 or more identical lines than TWIN_BASELINE allows
  readme-length    README.md is longer than 200 lines
  doc-path         a doc names a repository path (in backticks or a markdown link) that does
                   not exist

Every violation is one line, file:line: rule: what. The exit status is 1 when there is one.
"""

import argparse
import glob
import os
import re
import sys

MAX_FUNCTION_LINES = 80
MIN_TWIN_RUN = 6
MAX_README_LINES = 200

# Functions longer than MAX_FUNCTION_LINES that are allowed: (file, function) -> reason.
# Only numerical kernels that read better whole belong here.
FUNCTION_ALLOWLIST = {
    ("backends/nonsmooth/bundle-dca/src/bundle_dca_minimizer.cpp", "solve_qp"):
        "the bundle step's active-set QP: one loop of Newton step, ratio test and multiplier check",
}

# To split: long functions that are plumbing, in files being changed elsewhere. Printed as
# warnings, not failures, until they are split into named steps.
FUNCTION_TO_SPLIT = {
}

# Twin pairs that share runs of lines today: (file, twin) -> number of shared runs. The check
# fails when a pair shares more; lower the number when a pair shares fewer.
TWIN_BASELINE = {
    ("core/vem/include/hemivem/vem/element.hpp", "core/vem/include/hemivem/vem/element3d.hpp"): 1,
}

# Doc references that look like repository paths but are not: (doc, path) -> reason.
DOC_PATH_IGNORE = {
    ("docs/reference/engines.md", "hemivem/engine_names.hpp"):
        "generated into the build folder by backends/CMakeLists.txt",
}

SOURCE_EXTENSIONS = (".cpp", ".hpp")
SKIPPED_DIRS = ("tests", "fuzz")  # for function-length only, besides build*/
DOCS = ("README.md", "python/README.md", "scenes/README.md")
PATH_EXTENSIONS = (
    ".cpp", ".hpp", ".h", ".in", ".md", ".py", ".sh", ".toml", ".txt", ".cmake", ".json",
    ".msh", ".geo", ".poly2d", ".png", ".csv", ".yml", ".yaml", ".cfg", ".ini", ".pyi",
)
OUTPUT_DIRS = ("out", "build")  # what a run or a build writes, never repository files


# ---------------------------------------------------------------------------------------------
# C++ lexing: comments, strings and character literals


def lex_cpp(text):
    """Returns (code, code_with_strings): both keep every newline, so that line numbers hold.

    In `code` comments, string and character literals and preprocessor lines are blanked; in
    `code_with_strings` only comments are.
    """
    code = []
    kept = []
    i = 0
    n = len(text)
    line_start = True  # only whitespace since the last newline

    def blank(segment):
        return "".join(c if c == "\n" else " " for c in segment)

    while i < n:
        c = text[i]
        if c == "/" and text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j == -1 else j
            code.append(blank(text[i:j]))
            kept.append(blank(text[i:j]))
            i = j
            continue
        if c == "/" and text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j == -1 else j + 2
            code.append(blank(text[i:j]))
            kept.append(blank(text[i:j]))
            i = j
            continue
        if c == "#" and line_start:
            # a preprocessor line with its continuations
            j = i
            while True:
                k = text.find("\n", j)
                if k == -1:
                    k = n
                    break
                if text[k - 1] == "\\":
                    j = k + 1
                    continue
                break
            segment = text[i:k]
            code.append(blank(segment))
            kept.append(re.sub(r"\s//.*", "", segment) if "\n" not in segment else segment)
            i = k
            continue
        raw = re.match(r'(?:u8|u|U|L)?R"([^()\\\s]{0,16})\(', text[i:i + 24])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = text.find(")" + raw.group(1) + '"', i + raw.end())
            end = n if end == -1 else end + len(raw.group(1)) + 2
            code.append(blank(text[i:end]))
            kept.append(text[i:end])
            i = end
            line_start = False
            continue
        if c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum() and _digit_separator(text, i))):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            code.append(c + blank(text[i + 1:j - 1]) + (c if j - 1 > i else ""))
            kept.append(text[i:j])
            i = j
            line_start = False
            continue
        code.append(c)
        kept.append(c)
        if c == "\n":
            line_start = True
        elif not c.isspace():
            line_start = False
        i += 1
    return "".join(code), "".join(kept)


def _digit_separator(text, i):
    """A ' between digits of a number (1'000'000) rather than a character literal."""
    j = i - 1
    while j >= 0 and (text[j].isalnum() or text[j] in "'."):
        j -= 1
    return text[j + 1].isdigit() and i + 1 < len(text) and text[i + 1].isalnum()


# ---------------------------------------------------------------------------------------------
# Function definitions: a brace matcher with namespaces, classes and structs as containers

QUALIFIERS = re.compile(
    r"""^(?:\s+|const\b|volatile\b|override\b|final\b|mutable\b|&&|&|
        noexcept\s*(?:\([^()]*(?:\([^()]*\)[^()]*)*\))?|throw\s*\(\s*\)|
        \[\[[^\]]*\]\]|__attribute__\s*\(\([^)]*\)\))*""",
    re.X,
)
CONTAINER = re.compile(r"^(?:\s|\[\[[^\]]*\]\]|typedef\b|export\b|inline\b)*(?:namespace|extern)\b")
TYPE = re.compile(r"^(?:\s|\[\[[^\]]*\]\]|typedef\b|export\b)*(class|struct|union|enum)\b\s*(?:\[\[[^\]]*\]\]\s*)?(?:alignas\s*\([^)]*\)\s*)?(?:class\b|struct\b)?\s*([\w:]*)")
NAME_BEFORE_PAREN = re.compile(r"(operator\s*(?:\(\s*\)|\[\s*\]|[^\s\w(]+|\w[\w\s:<>*&]*?)|~?[A-Za-z_][\w]*(?:\s*<[^<>()]*>)?(?:\s*::\s*~?[A-Za-z_]\w*(?:\s*<[^<>()]*>)?)*)\s*$")


def strip_templates(header):
    """The header without its leading template<...> clauses."""
    while True:
        m = re.match(r"\s*template\s*<", header)
        if not m:
            return header
        depth = 0
        for k in range(m.end() - 1, len(header)):
            if header[k] == "<":
                depth += 1
            elif header[k] == ">":
                depth -= 1
                if depth == 0:
                    header = header[k + 1:]
                    break
        else:
            return header


def paren_groups(header):
    """(start, end) of each top-level (...) of a header; end is one past the ')'."""
    groups = []
    depth = 0
    start = 0
    for k, c in enumerate(header):
        if c == "(":
            if depth == 0:
                start = k
            depth += 1
        elif c == ")" and depth > 0:
            depth -= 1
            if depth == 0:
                groups.append((start, k + 1))
    return groups


def top_level_equals(header):
    """Whether the header assigns at the top level (an initializer, not a function)."""
    depth = 0
    for k, c in enumerate(header):
        if c in "([<":
            depth += 1 if c != "<" else 0
        elif c in ")]":
            depth -= 1
        elif c == "=" and depth == 0:
            before = header[:k].rstrip()
            after = header[k + 1:k + 2]
            if after == "=" or before.endswith(("=", "!", "<", ">", "operator")) or re.search(r"operator\s*[-+*/%^&|<>!=]*$", before):
                continue
            return True
    return False


def classify(header):
    """What a '{' at container scope opens: ('container', name), ('type', name),
    ('function', name, ctor_init) or ('other', None)."""
    h = strip_templates(header)
    if CONTAINER.match(h):
        return ("container", "")
    m = TYPE.match(h)
    if m:
        kind = "type" if m.group(1) != "enum" else "other"
        return (kind, m.group(2).split("::")[-1])
    if top_level_equals(h):
        return ("other", None)
    for start, end in paren_groups(h):
        tail = h[end:]
        q = QUALIFIERS.match(tail)
        rest = tail[q.end():]
        if rest == "" or rest.startswith("->") or rest.startswith("requires") or (
            rest.startswith(":") and not rest.startswith("::")
        ):
            m = NAME_BEFORE_PAREN.search(h[:start])
            if not m:
                continue
            name = re.sub(r"\s+", "", m.group(1))
            if name in ("if", "for", "while", "switch", "catch", "return", "sizeof", "decltype", "alignas"):
                continue
            return ("function", name, rest.startswith(":"))
    return ("other", None)


def match_brace(code, k):
    """The index of the '}' that closes the '{' at k."""
    depth = 0
    for j in range(k, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


def functions(code):
    """Yields (name, open_line, close_line) for each function definition of lexed code."""
    line_of = _line_index(code)
    found = []

    def scan(begin, end, scope):
        header_start = begin
        k = begin
        while k < end:
            c = code[k]
            if c == ";":
                header_start = k + 1
            elif c == "}":
                header_start = k + 1
            elif c == "{":
                header = code[header_start:k]
                close = match_brace(code, k)
                if header.count("(") > header.count(")"):
                    # braces inside parentheses: a default argument or an expression
                    k = close + 1
                    continue
                kind = classify(header)
                if kind[0] == "function" and kind[2] and re.search(r"[\w>]\s*$", header):
                    # a member initializer's braces inside a constructor's init list
                    k = close + 1
                    continue
                if kind[0] == "container":
                    scan(k + 1, close, scope)
                elif kind[0] == "type":
                    scan(k + 1, close, scope + [kind[1]] if kind[1] else scope)
                elif kind[0] == "function":
                    name = kind[1]
                    if scope and "::" not in name:
                        name = "::".join(scope) + "::" + name
                    found.append((name, line_of(k), line_of(close)))
                header_start = close + 1
                k = close + 1
                continue
            k += 1

    scan(0, len(code), [])
    return found


def _line_index(text):
    starts = [0]
    for k, c in enumerate(text):
        if c == "\n":
            starts.append(k + 1)

    def line_of(offset):
        lo, hi = 0, len(starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if starts[mid] <= offset:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    return line_of


def body_lines(open_line, close_line):
    """Lines of a body between its braces."""
    return max(0, close_line - open_line - 1)


# ---------------------------------------------------------------------------------------------
# The tree


def walk_tree(root, skip=()):
    """os.walk of the repository without hidden folders, build*/, out/ and the top folders `skip`."""
    for folder, dirs, files in os.walk(root):
        rel = os.path.relpath(folder, root)
        dirs[:] = sorted(
            d for d in dirs
            if not d.startswith(".")
            and not (rel == "." and (d.startswith("build") or d in OUTPUT_DIRS or d in skip))
        )
        yield folder, rel, files


def source_files(root):
    """Every .cpp and .hpp of the repository, relative, sorted."""
    result = []
    for _, rel, files in walk_tree(root):
        for f in files:
            if f.endswith(SOURCE_EXTENSIONS):
                result.append(os.path.normpath(os.path.join(rel, f)))
    return sorted(result)


def read(root, rel):
    with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
        return f.read()


class Report:
    def __init__(self, verbose):
        self.verbose = verbose
        self.violations = []
        self.warnings = []

    def violation(self, where, rule, what):
        self.violations.append(f"{where}: {rule}: {what}")

    def warning(self, where, rule, what):
        self.warnings.append(f"{where}: {rule} (warning): {what}")

    def info(self, text):
        if self.verbose:
            print(text)


def check_functions(root, files, report):
    over = []  # (file, line, name, lines, status)
    seen = set()
    checked = 0
    for rel in files:
        if rel.split(os.sep)[0] in SKIPPED_DIRS:
            continue
        code, _ = lex_cpp(read(root, rel))
        if code.count("{") != code.count("}"):
            report.warning(rel, "function-length", "unbalanced braces; functions may be miscounted")
        for name, open_line, close_line in functions(code):
            checked += 1
            lines = body_lines(open_line, close_line)
            if lines <= MAX_FUNCTION_LINES:
                continue
            key = (rel.replace(os.sep, "/"), name)
            seen.add(key)
            where = f"{key[0]}:{open_line}"
            if key in FUNCTION_ALLOWLIST:
                over.append((key, "allowed"))
                report.info(f"{where}: {name}: {lines} lines, allowed: {FUNCTION_ALLOWLIST[key]}")
            elif key in FUNCTION_TO_SPLIT:
                over.append((key, "to split"))
                report.warning(where, "function-length",
                               f"{name} has {lines} lines (> {MAX_FUNCTION_LINES}), to split: {FUNCTION_TO_SPLIT[key]}")
            else:
                over.append((key, "new"))
                report.violation(where, "function-length",
                                 f"{name} has {lines} lines (> {MAX_FUNCTION_LINES}); split it into named steps")
    for key in sorted(set(FUNCTION_ALLOWLIST) | set(FUNCTION_TO_SPLIT)):
        if key not in seen:
            report.warning(key[0], "function-length",
                           f"{key[1]} is no longer over {MAX_FUNCTION_LINES} lines (or gone): drop it from the allowlist")
    report.info(f"function-length: {checked} function bodies measured")
    return over


# ---------------------------------------------------------------------------------------------
# Twins: foo.cpp and foo3d.cpp


def twin_pairs(files):
    present = set(files)
    pairs = []
    for rel in files:
        stem, ext = os.path.splitext(rel)
        for twin in (stem + "3d" + ext, stem + "_3d" + ext):
            if twin in present:
                pairs.append((rel, twin))
    return pairs


def normalised_lines(root, rel):
    """[(line, text)]: whitespace collapsed; blank lines, comments, lone braces and #include
    lines dropped."""
    _, kept = lex_cpp(read(root, rel))
    result = []
    for number, line in enumerate(kept.split("\n"), start=1):
        text = " ".join(line.split())
        if not text or re.fullmatch(r"[{}();,\s]*", text) or re.match(r"#\s*include\b", text):
            continue
        result.append((number, text))
    return result


def shared_runs(a, b):
    """Maximal runs of at least MIN_TWIN_RUN consecutive equal lines: [(line_a, line_b, length)]."""
    where = {}
    for j, (_, text) in enumerate(b):
        where.setdefault(text, []).append(j)
    runs = []
    for i, (_, text) in enumerate(a):
        for j in where.get(text, ()):
            if i > 0 and j > 0 and a[i - 1][1] == b[j - 1][1]:
                continue  # not the start of a run
            length = 0
            while i + length < len(a) and j + length < len(b) and a[i + length][1] == b[j + length][1]:
                length += 1
            if length >= MIN_TWIN_RUN:
                runs.append((a[i][0], b[j][0], length))
    return runs


def check_twins(root, files, report):
    measures = []
    for first, second in twin_pairs(files):
        runs = shared_runs(normalised_lines(root, first), normalised_lines(root, second))
        key = (first.replace(os.sep, "/"), second.replace(os.sep, "/"))
        baseline = TWIN_BASELINE.get(key, 0)
        measures.append((key, len(runs), sum(r[2] for r in runs)))
        if len(runs) > baseline:
            for line_a, line_b, length in runs:
                report.violation(f"{key[1]}:{line_b}", "twin-overlap",
                                 f"{length} lines the same as {key[0]}:{line_a}")
            report.violation(key[1], "twin-overlap",
                             f"shares {len(runs)} run(s) of >= {MIN_TWIN_RUN} lines with {key[0]} (baseline {baseline}): "
                             "share the code instead of copying it")
        elif baseline:
            report.info(f"{key[1]}: twin-overlap: known: {len(runs)} shared runs with {key[0]} (baseline {baseline})")
            if len(runs) < baseline:
                report.warning(key[1], "twin-overlap",
                               f"shares {len(runs)} run(s) with {key[0]}: lower its baseline from {baseline} to {len(runs)}")
        else:
            report.info(f"{key[1]}: twin-overlap: no shared runs with {key[0]}")
    for key, baseline in sorted(TWIN_BASELINE.items()):
        if key not in dict((m[0], m) for m in measures):
            report.warning(key[1], "twin-overlap", f"the pair with {key[0]} is gone: drop its baseline")
    return measures


# ---------------------------------------------------------------------------------------------
# Docs


def doc_files(root):
    docs = [d for d in DOCS if os.path.isfile(os.path.join(root, d))]
    for folder, dirs, files in os.walk(os.path.join(root, "docs")):
        dirs.sort()
        for f in sorted(files):
            if f.endswith(".md"):
                docs.append(os.path.relpath(os.path.join(folder, f), root))
    return docs


def include_dirs(root):
    """The folders that hold hemivem/... headers."""
    return sorted(folder for folder, _, _ in walk_tree(root, SKIPPED_DIRS) if os.path.basename(folder) == "include")


def expand_braces(text):
    m = re.search(r"\{([^{}]*)\}", text)
    if not m:
        return [text]
    result = []
    for part in m.group(1).split(","):
        result.extend(expand_braces(text[:m.start()] + part + text[m.end():]))
    return result


def inline_code_spans(line):
    """The contents of the `code spans` of a line of markdown."""
    spans = []
    for m in re.finditer(r"(`+)(.+?)(?<!`)\1(?!`)", line):
        spans.append(m.group(2).strip())
    return spans


def link_targets(line):
    """The targets of the inline markdown links and images of a line."""
    return [m.group(1) for m in re.finditer(r"\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)", line)]


def path_candidates(span, top_dirs):
    """The words of a code span that are clearly repository paths."""
    result = []
    for word in span.split():
        word = word.strip(",;.()'\"")
        word = re.sub(r":\d+(?:-\d+)?$", "", word)  # file:line
        if word.startswith("-") or "/" not in word or "://" in word or "=" in word:
            continue
        if any(c in word for c in "<>$?[]") or word.startswith("/") or word.startswith("~"):
            continue
        first = word.split("/")[0]
        if first in (".", ".."):
            pass
        elif first not in top_dirs:
            continue
        if first.startswith("build") or first in OUTPUT_DIRS:
            continue
        for path in expand_braces(word):
            if path.endswith("/") or path.endswith(PATH_EXTENSIONS) or os.path.basename(path) == "CMakeLists.txt":
                result.append(path)
    return result


def resolve(root, doc, path, includes):
    """Whether path names something in the repository: from the top, from the doc's folder, or
    a header from an include folder (hemivem/vem/element.hpp, or vem/element.hpp for short)."""
    path = path.split("#")[0]
    if not path:
        return True
    candidates = [os.path.join(root, path), os.path.join(root, os.path.dirname(doc), path)]
    candidates += [os.path.join(folder, path) for folder in includes]
    candidates += [os.path.join(folder, "hemivem", path) for folder in includes]
    if "*" in path:
        return any(glob.glob(c) for c in candidates)
    return any(os.path.exists(c) for c in candidates)


def check_docs(root, report):
    includes = include_dirs(root)
    # the first folder of a path that is clearly the repository's: a top folder (.ci too), hemivem/
    # or a module's header folder (vem/element.hpp)
    top_dirs = {d for d in os.listdir(root) if os.path.isdir(os.path.join(root, d)) and d != ".git"}
    top_dirs.add("hemivem")
    for folder in includes:
        if os.path.isdir(os.path.join(folder, "hemivem")):
            top_dirs.update(d for d in os.listdir(os.path.join(folder, "hemivem"))
                            if os.path.isdir(os.path.join(folder, "hemivem", d)))
    used_ignores = set()
    checked = 0
    for doc in doc_files(root):
        folder = os.path.join(root, os.path.dirname(doc))
        doc_dirs = {d for d in os.listdir(folder) if os.path.isdir(os.path.join(folder, d))}
        fenced = False
        for number, line in enumerate(read(root, doc).split("\n"), start=1):
            if re.match(r"\s*(```|~~~)", line):
                fenced = not fenced
                continue
            if fenced:
                continue
            names = []
            for span in inline_code_spans(line):
                names.extend(path_candidates(span, top_dirs | doc_dirs))
            for target in link_targets(re.sub(r"`[^`]*`", "", line)):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                    continue  # a URL, an address or an anchor
                target = target.split("#")[0]
                first = target.split("/")[0]
                if first.startswith("build") or first in OUTPUT_DIRS:
                    continue
                names.append(target)
            for name in names:
                checked += 1
                key = (doc.replace(os.sep, "/"), name)
                if key in DOC_PATH_IGNORE:
                    used_ignores.add(key)
                    continue
                if not resolve(root, doc, name, includes):
                    report.violation(f"{key[0]}:{number}", "doc-path", f"{name} does not exist")
    for key in sorted(set(DOC_PATH_IGNORE) - used_ignores):
        report.warning(key[0], "doc-path", f"the ignored reference {key[1]} is gone: drop it from DOC_PATH_IGNORE")
    report.info(f"doc-path: {checked} references to repository paths checked in {len(doc_files(root))} docs")


def check_readme(root, report):
    path = os.path.join(root, "README.md")
    if not os.path.isfile(path):
        return 0
    lines = len(read(root, "README.md").splitlines())
    if lines > MAX_README_LINES:
        report.violation(f"README.md:{MAX_README_LINES + 1}", "readme-length",
                         f"README.md has {lines} lines (> {MAX_README_LINES}); move detail to the docs it links")
    return lines


def main():
    parser = argparse.ArgumentParser(description="Checks the house rules on the source tree.")
    parser.add_argument("--verbose", "-v", action="store_true", help="list what was checked")
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."),
                        help="the repository (default: the one holding this script)")
    args = parser.parse_args()
    root = os.path.normpath(args.root)
    report = Report(args.verbose)

    files = source_files(root)
    over = check_functions(root, files, report)
    twins = check_twins(root, files, report)
    readme = check_readme(root, report)
    check_docs(root, report)

    for line in report.warnings:
        print(line)
    for line in report.violations:
        print(line)
    allowed = sum(1 for _, status in over if status == "allowed")
    to_split = sum(1 for _, status in over if status == "to split")
    new = sum(1 for _, status in over if status == "new")
    shared = sum(m[1] for m in twins)
    sharing = sum(1 for m in twins if m[1])
    print(
        f"check-house: functions over {MAX_FUNCTION_LINES} lines: {len(over)} "
        f"({allowed} allowlisted kernels, {to_split} to split, {new} not allowed); "
        f"twin pairs: {len(twins)}, {sharing} sharing {shared} runs of >= {MIN_TWIN_RUN} lines; "
        f"README.md: {readme} lines; "
        f"{len(report.violations)} violations"
    )
    return 1 if report.violations else 0


if __name__ == "__main__":
    sys.exit(main())
