#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Fails (exit 1, one "file:line: [kind] text" per finding) when a comment in a tracked file names
# something a clone of the repository does not have:
#   path      a folder on a build machine (the work tree's parent, a shared folder beside it);
#   issue     an issue or pull-request number of the project's tracker;
#   document  (with --documents only) a .md file that is not in the tree, or a source document
#             cited by its file number instead of its title.
# A comment cites a public datasheet, a public repository or the repository's own docs/ instead.
# Comments are told from code per language (C++ and JavaScript strings, raw strings and block
# comments; '#' comments in CMake, shell, YAML, systemd, udev and make files); every line of a
# Markdown file counts. Code that locates test data (tests/support/testdata.hpp) is not a comment.
#   tools/check_comments.sh [--documents] [FILE...]      (default: every tracked file)
set -euo pipefail
cd "$(dirname "$0")/.."

documents=0
files=()
for arg in "$@"; do
  case "$arg" in
    --documents) documents=1 ;;
    -h | --help)
      sed -n '3,13p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *) files+=("$arg") ;;
  esac
done
if [ "${#files[@]}" -eq 0 ]; then
  mapfile -t files < <(git ls-files)
fi

# Basenames of the tracked Markdown files: a cited document must be one of them.
known_md=$(git ls-files '*.md' | sed 's|.*/||' | sort -u | tr '\n' ' ')

# Sets `lang` for a path: c, js, hash (comments start with '#'), text (all of it) or none.
lang_of() {
  case "$1" in
    *.cpp | *.hpp | *.h | *.cc | *.c | *.ino) lang=c ;;
    *.js | *.mjs) lang=js ;;
    *.md) lang=text ;;
    CMakeLists.txt | */CMakeLists.txt | *.cmake | *.sh | *.bash | *.yaml | *.yml | *.rules | \
      *.service | *.sysusers | *.supp | Makefile | */Makefile | *.mk | .clang-format | \
      .clang-tidy | .gitignore | */.gitignore | .ci/* | scripts/*) lang=hash ;;
    *) lang=none ;;
  esac
}

declare -A group=()
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  lang_of "$f"
  [ "$lang" = none ] && continue
  group[$lang]+="$f"$'\n'
done

status=0
for lang in "${!group[@]}"; do
  mapfile -t batch < <(printf '%s' "${group[$lang]}")
  awk -v lang="$lang" -v sq="'" -v documents="$documents" -v known_md="$known_md" '
    BEGIN {
      found = 0
      n = split(known_md, k, " "); for (i = 1; i <= n; i++) md[tolower(k[i])] = 1
    }
    FNR == 1 { in_block = 0; in_raw = 0; raw_end = ""; in_tpl = 0 }
    # Comment text of one line of C++ or JavaScript; keeps block, raw-string and template state.
    function c_comments(s,    out, i, c, nx, q, p, d) {
      out = ""; i = 1
      while (i <= length(s)) {
        if (in_block) {
          p = index(substr(s, i), "*/")
          if (p == 0) { out = out " " substr(s, i); return out }
          out = out " " substr(s, i, p - 1); i += p + 1; in_block = 0; continue
        }
        if (in_raw) {
          p = index(substr(s, i), raw_end)
          if (p == 0) return out
          i += p + length(raw_end) - 1; in_raw = 0; continue
        }
        if (in_tpl) {
          c = substr(s, i, 1)
          if (c == "\\") { i += 2; continue }
          if (c == "`") in_tpl = 0
          i++; continue
        }
        c = substr(s, i, 1); nx = substr(s, i + 1, 1)
        if (c == "/" && nx == "/") return out " " substr(s, i + 2)
        if (c == "/" && nx == "*") { in_block = 1; i += 2; continue }
        if (c == "`" && lang == "js") { in_tpl = 1; i++; continue }
        if (c == "\"" && lang == "c" && i > 1 && substr(s, i - 1, 1) == "R" && \
            (i == 2 || substr(s, i - 2, 1) !~ /[A-Za-z0-9_]/ || substr(s, i - 3, 2) == "u8" || \
             substr(s, i - 2, 1) ~ /[uUL]/)) {
          p = index(substr(s, i + 1), "(")
          if (p == 0) { i++; continue }
          d = substr(s, i + 1, p - 1); raw_end = ")" d "\""; in_raw = 1; i += p + 1; continue
        }
        if (c == "\"" || c == sq) {
          # A digit separator (1'\''000) is not a character literal.
          if (c == sq && lang == "c" && i > 1 && substr(s, i - 1, 1) ~ /[0-9A-Fa-f]/ && \
              nx ~ /[0-9A-Fa-f]/) { i++; continue }
          q = c; i++
          while (i <= length(s)) {
            c = substr(s, i, 1)
            if (c == "\\") { i += 2; continue }
            i++
            if (c == q) break
          }
          continue
        }
        i++
      }
      return out
    }
    # Comment text of one line of a "#"-comment language: from a "#" at the start of the line or
    # after a blank, outside quotes.
    function hash_comments(s,    i, c, q) {
      q = ""
      for (i = 1; i <= length(s); i++) {
        c = substr(s, i, 1)
        if (q != "") { if (c == "\\" && q == "\"") i++; else if (c == q) q = ""; continue }
        if (c == "\"" || c == sq) { q = c; continue }
        if (c == "#" && (i == 1 || substr(s, i - 1, 1) ~ /[ \t]/)) return substr(s, i + 1)
      }
      return ""
    }
    function report(kind) {
      line = $0; sub(/^[ \t]+/, "", line)
      if (length(line) > 150) line = substr(line, 1, 147) "..."
      printf "%s:%d: [%s] %s\n", FILENAME, FNR, kind, line
      found = 1
    }
    # True when t names a tracker number that is not one of a public repository: a number after an
    # "owner/repo" prefix cites a public tracker and is allowed.
    function names_issue(t) {
      gsub(/[a-z0-9_.-]+\/[a-z0-9_.-]+ +(issues?|pull requests?|pr) *#?[0-9]+/, "", t)
      gsub(/[a-z0-9_.-]+\/[a-z0-9_.-]+#[0-9]+/, "", t)
      return t ~ /(^|[^a-z0-9_\/.-])(issues?|pull requests?|pr) *#?[0-9]+/ || \
             t ~ /(^|[ \t(])#[0-9]+([^0-9a-z_]|$)/
    }
    function names_missing_document(t,    u, name) {
      if (t ~ /(^|[^a-z0-9_])seeds?\// || t ~ /(document|doc|seed)s? +0[0-9][0-9]/) return 1
      u = t
      while (match(u, /[a-z0-9_.\/-]*[a-z0-9_-]\.md([^a-z0-9_]|$)/)) {
        name = substr(u, RSTART, RLENGTH); sub(/[^a-z0-9_]$/, "", name); sub(/.*\//, "", name)
        if (!(name in md)) return 1
        u = substr(u, RSTART + RLENGTH)
      }
      return 0
    }
    {
      if (lang == "c" || lang == "js") t = c_comments($0)
      else if (lang == "hash") t = hash_comments($0)
      else t = $0
      if (t == "") next
      t = tolower(t)
      if (t ~ /\/work\// || t ~ /\.\.\/shared([^a-z0-9_]|$)/ || t ~ /shared\/(docs|seeds|testdata)/)
        report("path")
      else if (names_issue(t)) report("issue")
      else if (documents == 1 && names_missing_document(t)) report("document")
    }
    END { exit found }
  ' "${batch[@]}" || status=1
done

if [ "$status" -ne 0 ]; then
  echo "check_comments: the comments above name what a clone does not have; cite a public" \
    "datasheet or the repository's docs/ instead" >&2
  exit 1
fi
echo "check_comments: ${#files[@]} files, no machine path or issue number in a comment"
