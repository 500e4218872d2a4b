#!/usr/bin/env python3
"""The Python module only converts types and calls the library (docs/architecture.md): no
function in python/src is longer than 80 lines. A function is every body at namespace or class
scope (free functions, member functions, PYBIND11_MODULE), from the first line of its signature
to its closing brace; the lambdas inside it count as its lines. Comments, strings and character
literals are blanked first, so their braces do not count."""
import pathlib
import re
import sys

LIMIT = 80
ROOT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")


def blank(text):
    """The text with comments, string and character literals replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            open_paren = text.find("(", i + 2)
            delim = text[i + 2 : open_paren]
            j = text.find(")" + delim + '"', open_paren)
            j = n if j < 0 else j + len(delim) + 2
        elif c in "\"'" and not (c == "'" and i > 0 and text[i - 1].isalnum()):  # 1'000 is a digit separator
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j += 1
        else:
            out.append(c)
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", text[i:j]))
        i = j
    return "".join(out)


CONTAINER = re.compile(r'(\bnamespace\b|\bextern\s+"|\b(class|struct|union|enum)\b[^()=]*$)')


def functions(text):
    """(name, first line, last line) of every function body at namespace or class scope."""
    code = blank(text)
    found = []
    stack = []  # per open brace: "container", "function" (with its start) or "inner"
    head_start = 0  # where the declaration before the next brace begins
    for i, c in enumerate(code):
        if c == "{":
            head = code[head_start:i]
            if stack and stack[-1][0] != "container":
                stack.append(("inner",))
            elif CONTAINER.search(head.strip()) or head.rstrip().endswith("="):
                stack.append(("container",) if CONTAINER.search(head.strip()) else ("inner",))
            else:
                start = head_start + len(head) - len(head.lstrip())
                name = re.sub(r"\s+", " ", head.strip())[:70]
                stack.append(("function", start, name))
            head_start = i + 1
        elif c == "}":
            if stack:
                top = stack.pop()
                if top[0] == "function":
                    found.append((top[2], code.count("\n", 0, top[1]) + 1, code.count("\n", 0, i) + 1))
            head_start = i + 1
        elif c == ";" or (c == ":" and stack and stack[-1][0] == "container" and re.search(r"\b(public|private|protected)\s*$", code[head_start:i])):
            head_start = i + 1
    return found


# The scanner itself, on a sample whose answer is known: braces in comments, strings and raw
# strings do not count, namespaces and classes are containers, lambdas count in their function.
SAMPLE = """namespace a {
// } not a brace
struct S {
  int f() const { return 1; }
 public:
  std::string g() { return "}{"; }
};
void long_one() {
  auto l = [] {
    return R"x({)x";
  };
""" + "  x();\n" * 76 + """}
}  // namespace a
"""
assert [(n, a, b) for n, a, b in functions(SAMPLE)] == [
    ("int f() const", 4, 4), ("std::string g()", 6, 6), ("void long_one()", 8, 88)]  # 81 lines, functions(SAMPLE)

problems = []
count = 0
for f in sorted((ROOT / "python" / "src").glob("*.[ch]*")):
    for name, first, last in functions(f.read_text()):
        count += 1
        if last - first + 1 > LIMIT:
            problems.append(f"{f.relative_to(ROOT)}:{first}: {name} is {last - first + 1} lines (at most {LIMIT})")
for p in problems:
    print(p)
print(f"binding functions: {len(problems)} over {LIMIT} lines of {count} in python/src")
sys.exit(1 if problems or count == 0 else 0)
