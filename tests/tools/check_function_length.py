#!/usr/bin/env python3
"""Check that no function body in the C++ sources is longer than a limit.

Finds every function body in *.cpp / *.hpp under cpp/src, cpp/include, cpp/cli and
cpp/bindings and lists those longer than --max lines (default 120), counted from the line with
the body's opening brace to the line with its closing brace, both included. Lambdas inside a
function count as part of that function; a lambda stored in a variable at namespace or class
scope counts as a function of its own (named after the variable).

The scan is a small parser of brace structure, not a regular expression: it tokenizes the file
(skipping comments, string literals including raw strings, character literals, digit separators
and preprocessor lines), keeps a stack of scopes (namespace, class, function, block) and decides,
for each '{' met at namespace or class scope, whether it opens a function body from the tokens
of the declaration before it.

Usage:
  check_function_length.py [--max N] [--root DIR] [PATH...]   exit 1 and list the long ones
  check_function_length.py --self-test                         check the parser on fixtures
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from dataclasses import dataclass

DEFAULT_MAX_LINES = 120
DEFAULT_DIRS = ("cpp/src", "cpp/include", "cpp/cli", "cpp/bindings")
EXTENSIONS = (".cpp", ".hpp")

# Keywords that may precede a parenthesised expression and a '{' without declaring a function.
CONTROL_KEYWORDS = {"if", "for", "while", "switch", "catch", "do", "else", "return", "sizeof",
                    "decltype", "alignas", "static_assert", "requires"}
CLASS_KEYWORDS = {"class", "struct", "union", "enum"}


@dataclass
class Token:
    text: str
    line: int


@dataclass
class LongFunction:
    path: str
    line: int
    name: str
    length: int

    def __str__(self) -> str:
        return f"{self.path}:{self.line} {self.name} {self.length}"


_RAW_PREFIX = re.compile(r'(?:u8|u|U|L)?R"([^()\\\s]{0,16})\(')
_IDENT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
_NUMBER = re.compile(r"\.?[0-9](?:[eEpP][+-]|[0-9A-Za-z_.']|'(?=[0-9A-Za-z]))*")
_PUNCT3 = ("<<=", ">>=", "->*", "...", "<=>")
_PUNCT2 = ("::", "->", "++", "--", "<<", ">>", "<=", ">=", "==", "!=", "&&", "||", "+=", "-=",
           "*=", "/=", "%=", "&=", "|=", "^=", ".*", "##")


def tokenize(text: str) -> list[Token]:
    """Splits C++ source into tokens with line numbers; comments, literals' contents and
    preprocessor lines are dropped (a literal becomes one token "<str>" or "<chr>")."""
    tokens: list[Token] = []
    i, line, n = 0, 1, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
            at_line_start = True
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if c == "\\" and i + 1 < n and text[i + 1] == "\n":
            i += 2
            line += 1
            continue
        if at_line_start and c == "#":
            i, line = _skip_preprocessor(text, i, line)
            continue
        at_line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            line += text.count("\n", i, end)
            i = end
            continue
        raw = _RAW_PREFIX.match(text, i)
        if raw:
            closing = ")" + raw.group(1) + '"'
            end = text.find(closing, raw.end())
            end = n if end < 0 else end + len(closing)
            tokens.append(Token("<str>", line))
            line += text.count("\n", i, end)
            i = end
            continue
        ident = _IDENT.match(text, i)
        if ident:
            word = ident.group(0)
            nxt = ident.end()
            if word in ("u8", "u", "U", "L") and nxt < n and text[nxt] in "\"'":
                i = nxt  # encoding prefix of a literal: the literal follows
                continue
            tokens.append(Token(word, line))
            i = nxt
            continue
        if c.isdigit() or (c == "." and i + 1 < n and text[i + 1].isdigit()):
            number = _NUMBER.match(text, i)
            tokens.append(Token("<num>", line))
            i = number.end()
            continue
        if c in "\"'":
            end = _skip_quoted(text, i, c)
            tokens.append(Token("<str>" if c == '"' else "<chr>", line))
            line += text.count("\n", i, end)
            i = end
            continue
        for punct in _PUNCT3 + _PUNCT2:
            if text.startswith(punct, i):
                tokens.append(Token(punct, line))
                i += len(punct)
                break
        else:
            tokens.append(Token(c, line))
            i += 1
    return tokens


def _skip_preprocessor(text: str, i: int, line: int) -> tuple[int, int]:
    """Skips a preprocessor directive with its backslash continuations and comments."""
    n = len(text)
    while i < n:
        if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
            i += 2
            line += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            line += text.count("\n", i, end)
            i = end
        elif text.startswith("//", i) or text[i] == "\n":
            return i if text[i] == "\n" else text.find("\n", i) % (n + 1), line
        else:
            i += 1
    return i, line


def _skip_quoted(text: str, i: int, quote: str) -> int:
    """Returns the index past the string or character literal starting at text[i]."""
    n = len(text)
    j = i + 1
    while j < n:
        if text[j] == "\\":
            j += 2
        elif text[j] == quote:
            return j + 1
        elif text[j] == "\n":  # unterminated: stop at the line end
            return j
        else:
            j += 1
    return n


def _matching_open(decl: list[Token], close_index: int, open_text: str, close_text: str) -> int:
    depth = 0
    for k in range(close_index, -1, -1):
        if decl[k].text == close_text:
            depth += 1
        elif decl[k].text == open_text:
            depth -= 1
            if depth == 0:
                return k
    return -1


def _top_level(decl: list[Token]) -> list[tuple[int, Token]]:
    """Tokens of a declaration that are outside (), [] and {} (angle brackets are ignored)."""
    out, depth = [], 0
    for k, tok in enumerate(decl):
        if tok.text in ("(", "[", "{"):
            if depth == 0:
                out.append((k, tok))
            depth += 1
        elif tok.text in (")", "]", "}"):
            depth -= 1
            if depth == 0:
                out.append((k, tok))
        elif depth == 0:
            out.append((k, tok))
    return out


def _qualified_name_before(decl: list[Token], k: int) -> str:
    """The (possibly qualified, template or operator) name ending just before index k."""
    parts: list[str] = []
    j = k - 1
    for back in range(1, 4):  # operator(), operator[], operator==, operator<<, ...
        if k - back >= 0 and decl[k - back].text == "operator":
            parts.append("".join(t.text for t in decl[k - back:k]))
            j = k - back - 1
            break
    while j >= 0:
        text = decl[j].text
        want_name = not parts or parts[-1] in ("::",)
        if want_name and text == ">":  # template-id such as Outer<T>
            open_index = _matching_open(decl, j, "<", ">")
            if open_index < 1 or not _IDENT.fullmatch(decl[open_index - 1].text):
                break
            parts.append(decl[open_index - 1].text +
                         "".join(t.text for t in decl[open_index:j + 1]))
            j = open_index - 2
        elif want_name and _IDENT.fullmatch(text):
            parts.append(text)
            j -= 1
            if j >= 0 and decl[j].text == "~":
                parts[-1] = "~" + text
                j -= 1
        elif not want_name and text == "::":
            parts.append(text)
            j -= 1
        else:
            break
    return "".join(reversed(parts))


def _parameter_list(decl: list[Token], top: list[tuple[int, Token]]) -> int | None:
    """Index in decl of the '(' opening the parameter list, or None when there is none."""
    parens = [k for k, t in top if t.text == "("]
    if not parens:
        return None
    first = parens[0]
    if first >= 1 and decl[first - 1].text == "operator" and len(parens) > 1:
        return parens[1]  # operator()(...): the first pair is the operator's name
    return first


def _closing(decl: list[Token], open_index: int) -> int:
    depth = 0
    for k in range(open_index, len(decl)):
        if decl[k].text == "(":
            depth += 1
        elif decl[k].text == ")":
            depth -= 1
            if depth == 0:
                return k
    return len(decl) - 1


def classify_scope(decl: list[Token]) -> tuple[str, str]:
    """Kind of the '{' that follows the declaration tokens decl ('namespace', 'class',
    'function' or 'block') and, for a function, its name."""
    while len(decl) > 1 and decl[0].text in ("public", "private", "protected") \
            and decl[1].text == ":":
        decl = decl[2:]
    words = [t.text for t in decl]
    if not words:
        return "block", ""
    if "namespace" in words[:3] or (words[0] == "extern" and len(words) == 2):
        return "namespace", ""
    depth = sum(1 if w in ("(", "[") else -1 if w in (")", "]") else 0 for w in words)
    if depth > 0:
        return "block", ""  # inside an unclosed ( or [: a braced argument such as `x = {}`
    top = _top_level(decl)
    top_words = [t.text for _, t in top]
    if "=" in top_words:  # a variable: a lambda at namespace scope or a brace initializer
        eq = top_words.index("=")
        after = [t for _, t in top[eq + 1:]]
        if after and after[0].text == "[" and any(t.text == "(" for t in after):
            return "function", _qualified_name_before(decl, top[eq][0]) + " (lambda)"
        return "block", ""
    has_class_keyword = any(w in CLASS_KEYWORDS for w in top_words)
    params = _parameter_list(decl, top)
    if params is None:
        return ("class" if has_class_keyword else "block"), ""
    name = _qualified_name_before(decl, params)
    if not name or name in CONTROL_KEYWORDS:
        return ("class" if has_class_keyword else "block"), ""
    tail = [t.text for t in decl[_closing(decl, params) + 1:]]
    if ":" in tail and decl[-1].text not in (")", "}"):
        return "block", ""  # a member initializer such as x_{1} in a constructor's init list
    return "function", name


def find_functions(text: str) -> list[tuple[int, int, str]]:
    """Every function body in text as (first line, last line, name)."""
    stack: list[tuple[str, str, int, list[Token]]] = []  # (kind, name, line of '{', decl)
    decl: list[Token] = []
    functions: list[tuple[int, int, str]] = []
    for tok in tokenize(text):
        inside_code = any(kind in ("function", "block") for kind, _, _, _ in stack)
        if tok.text == "{":
            kind, name = ("block", "") if inside_code else classify_scope(decl)
            stack.append((kind, name, tok.line, decl))
            decl = []
        elif tok.text == "}":
            if not stack:
                decl = []
                continue
            kind, name, start, outer_decl = stack.pop()
            if kind == "function":
                functions.append((start, tok.line, name))
            still_in_code = any(k in ("function", "block") for k, _, _, _ in stack)
            if kind == "block" and not still_in_code:
                # A brace initializer (x_{1}, = {1, 2}): part of the declaration around it.
                decl = outer_decl + [Token("{", start), tok]
            else:
                decl = []
        elif tok.text == ";":
            decl = []
        elif not inside_code:
            decl.append(tok)
    return functions


def find_long_functions(path: str, text: str, max_lines: int) -> list[LongFunction]:
    found = []
    for start, end, name in find_functions(text):
        length = end - start + 1
        if length > max_lines:
            found.append(LongFunction(path, start, name, length))
    return found


def source_files(root: str, paths: list[str]) -> list[str]:
    files = []
    for entry in paths:
        full = os.path.join(root, entry)
        if os.path.isfile(full):
            files.append(entry)
            continue
        for folder, _, names in os.walk(full):
            for name in names:
                if name.endswith(EXTENSIONS):
                    files.append(os.path.relpath(os.path.join(folder, name), root))
    return sorted(files)


# ---- self-test -------------------------------------------------------------------------------

_FIXTURE = r'''
#include <string>
#define BRACES_IN_MACRO { {
namespace a { namespace b {
struct S : Base<int> {
  S() : x_{1}, y_(2) {
    int z = 0;
  }
  int get(std::initializer_list<int> keys = {}) const noexcept { return "}"[0] == '}'; }
  int x_{0}, y_;
};
}  // namespace b
// a comment with a brace {
/* a block comment { { */
const int kTable[] = {1, 2, 3};
const auto kLambda = [](int v) {
  return v + 1'000'000;
};
auto f(int n) -> int {
  auto g = [&](int m) {
    if (m > 0) {
      return R"x(raw } string {)x";
    }
    return "";
  };
  for (int i = 0; i < n; ++i) { g(i); }
  return n;
}
template <typename T> T Outer<T>::operator()(const T& t) const
{
  return t;
}
enum class Mode { A, B };
extern "C" {
void cfun() {}
}
}  // namespace a
'''

_EXPECTED = [(6, 8, "S"), (9, 9, "get"), (16, 18, "kLambda (lambda)"), (19, 28, "f"),
             (30, 32, "Outer<T>::operator()"), (35, 35, "cfun")]


def self_test() -> int:
    got = find_functions(_FIXTURE)
    failures = []
    if got != _EXPECTED:
        failures.append(f"functions found {got}, expected {_EXPECTED}")
    long = find_long_functions("fixture.cpp", _FIXTURE, 5)
    if [str(x) for x in long] != ["fixture.cpp:19 f 10"]:
        failures.append(f"long functions at limit 5: {[str(x) for x in long]}, "
                        "expected ['fixture.cpp:19 f 10']")
    if find_long_functions("fixture.cpp", _FIXTURE, 10):
        failures.append("a 10-line function is reported at limit 10")
    tokens = tokenize('x = u8"a{" + L\'{\' + 0x1\'F; // {\n/* { */ y')
    if [t.text for t in tokens] != ["x", "=", "<str>", "+", "<chr>", "+", "<num>", ";", "y"] \
            or tokens[-1].line != 2:
        failures.append(f"tokenize: {[(t.text, t.line) for t in tokens]}")
    for failure in failures:
        print("self-test failed: " + failure)
    if not failures:
        print(f"self-test passed: {len(got)} functions found in the fixture as expected")
    return 1 if failures else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="*", default=list(DEFAULT_DIRS),
                        help="files or folders relative to --root (default: %(default)s)")
    parser.add_argument("--max", type=int, default=DEFAULT_MAX_LINES,
                        help="longest allowed function body, lines (default: %(default)s)")
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), "..", ".."),
                        help="repository root (default: two folders above this script)")
    parser.add_argument("--self-test", action="store_true", help="check the parser and exit")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    root = os.path.normpath(args.root)
    files = source_files(root, args.paths)
    if not files:
        print(f"no C++ sources found under {root}: {args.paths}; pass --root of the repository")
        return 1
    long = []
    count = 0
    for path in files:
        with open(os.path.join(root, path), encoding="utf-8") as handle:
            text = handle.read()
        count += len(find_functions(text))
        long.extend(find_long_functions(path, text, args.max))
    for item in sorted(long, key=lambda x: -x.length):
        print(item)
    print(f"{len(long)} of {count} functions in {len(files)} files are longer than "
          f"{args.max} lines")
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
