#!/usr/bin/env python3
"""The Markdown files render as written: checked with a real CommonMark renderer (cmark).

For README.md, CONTRIBUTING.md, CHANGELOG.md and docs/*.md:
  - every code fence that opens is closed, and a closing fence has nothing after it
    (text after ``` does not close a fence: everything down to the next fence becomes code);
  - every line starting with '#' outside a fence is rendered by cmark as an <hN> heading of the
    same level and text, in the same order (so no heading was swallowed by a code block);
  - cmark renders as many code blocks as the file has fenced blocks;
  - every relative link or image points to a file of the repository, and nothing points
    outside it.

Run by `make test` (catkin_add_nosetests in cmake/docs.cmake). To check other files, e.g. an
old README:  python3 test/docs/markdown_test.py --check FILE...
"""
import glob
import html
import os
import re
import subprocess
import sys
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))

FENCE = re.compile(r'^ {0,3}(`{3,}|~{3,})(.*)$')
ATX = re.compile(r'^(#{1,6})(?:[ \t]+|$)(.*?)(?:[ \t]+#+)?[ \t]*$')
HEADING_HTML = re.compile(r'<h([1-6])>(.*?)</h\1>', re.S)
LINK_HTML = re.compile(r'(?:href|src)="([^"]*)"')
OUTSIDE = re.compile(r'[.][.]/shared|METHOD[.]md|DESIGN[.]md|[/]work[/]')


def markdown_files(root=ROOT):
    names = ['README.md', 'CONTRIBUTING.md', 'CHANGELOG.md']
    files = [os.path.join(root, n) for n in names if os.path.exists(os.path.join(root, n))]
    return files + sorted(glob.glob(os.path.join(root, 'docs', '**', '*.md'), recursive=True))


def render(text):
    return subprocess.run(['cmark', '--to', 'html'], input=text, capture_output=True,
                          text=True, check=True).stdout


def normalize(s):
    """Heading text without markup: letters and digits only, lower case."""
    s = html.unescape(re.sub(r'<[^>]+>', '', s))
    return re.sub(r'[^0-9a-z]', '', s.lower())


def scan(text):
    """Fences and headings as a reader of the source sees them (a fence line toggles).

    Returns (problems, headings [(level, text, line)], fenced block count)."""
    problems, headings = [], []
    fence = None  # (char, length, line) of the open fence
    blocks = 0
    for n, line in enumerate(text.split('\n'), 1):
        m = FENCE.match(line)
        if fence is None:
            if m:
                fence = (m.group(1)[0], len(m.group(1)), n)
                blocks += 1
                continue
            if line.startswith('#'):
                h = ATX.match(line)
                if not h:
                    problems.append('line %d starts with # but is not a heading: %r' % (n, line))
                else:
                    headings.append((len(h.group(1)), h.group(2), n))
        elif m and m.group(1)[0] == fence[0] and len(m.group(1)) >= fence[1]:
            if m.group(2).strip():
                problems.append('line %d: text after a closing code fence (%r): the fence of '
                                'line %d stays open' % (n, line.strip(), fence[2]))
            fence = None
    if fence is not None:
        problems.append('code fence opened at line %d is never closed' % fence[2])
    return problems, headings, blocks


def check_text(text, path):
    """Every problem of one Markdown file, as messages naming the line."""
    problems, headings, blocks = scan(text)
    out = render(text)
    rendered = [(int(level), body) for level, body in HEADING_HTML.findall(out)]
    expected = [(level, normalize(body)) for level, body, _ in headings]
    got = [(level, normalize(body)) for level, body in rendered]
    if expected != got:
        got_left = list(got)
        for level, body, n in headings:
            if (level, normalize(body)) in got_left:
                got_left.remove((level, normalize(body)))
            else:
                problems.append('line %d: %r is not rendered as an <h%d> heading'
                                % (n, '#' * level + ' ' + body, level))
        if not problems:
            problems.append('headings rendered %r, source has %r' % (got, expected))
    pre = out.count('<pre')
    if pre != blocks:
        problems.append('%d fenced code blocks in the source, %d rendered' % (blocks, pre))
    base = os.path.dirname(os.path.abspath(path))
    if not base.startswith(ROOT):  # a file from elsewhere (--check): links as if at the root
        base = ROOT
    for target in LINK_HTML.findall(out):
        target = html.unescape(target)
        if re.match(r'^[a-z][a-z0-9+.-]*:', target) or target.startswith('#'):
            continue
        file = os.path.normpath(os.path.join(base, target.split('#')[0]))
        if not file.startswith(ROOT + os.sep) and file != ROOT:
            problems.append('link %r points outside the repository' % target)
        elif not os.path.exists(file):
            problems.append('link %r: no such file' % target)
    for n, line in enumerate(text.split('\n'), 1):
        if OUTSIDE.search(line):
            problems.append('line %d points outside the repository: %r' % (n, line.strip()))
    return problems


def check_file(path):
    with open(path, encoding='utf-8') as f:
        return check_text(f.read(), path)


class MarkdownTest(unittest.TestCase):

    def test_files_exist(self):
        names = [os.path.relpath(p, ROOT) for p in markdown_files()]
        for required in ['README.md', 'CONTRIBUTING.md', 'CHANGELOG.md', 'docs/method.md',
                         'docs/ros_interface.md', 'docs/scene_format.md', 'docs/architecture.md',
                         'docs/benchmark.md']:
            self.assertIn(required, names)

    def test_every_file_renders_as_written(self):
        for path in markdown_files():
            with self.subTest(file=os.path.relpath(path, ROOT)):
                problems = check_file(path)
                self.assertEqual(problems, [], '\n'.join(problems))

    def test_detects_text_after_a_closing_fence(self):
        bad = 'Intro\n\n```bash\necho hi\n``` trailing text\n\n## Later\n\ntext\n'
        problems = check_text(bad, os.path.join(ROOT, 'README.md'))
        self.assertTrue(any('text after a closing code fence' in p for p in problems), problems)
        self.assertTrue(any("'## Later' is not rendered" in p for p in problems), problems)

    def test_detects_an_unclosed_fence(self):
        problems = check_text('# Title\n\n```\ncode\n', os.path.join(ROOT, 'README.md'))
        self.assertTrue(any('never closed' in p for p in problems), problems)


if __name__ == '__main__':
    if len(sys.argv) > 1 and sys.argv[1] == '--check':
        failed = False
        for p in sys.argv[2:]:
            problems = check_file(p)
            for msg in problems:
                print('%s: %s' % (p, msg))
            failed = failed or bool(problems)
        sys.exit(1 if failed else 0)
    unittest.main()
