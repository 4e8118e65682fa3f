#!/usr/bin/env bash
# Checks the fenced code blocks of the documentation against the program and the repository, so
# that an example never names a port, node, param, graph or file that does not exist:
#   - every block has an info string (```bash, ```yaml, ```text, ...), so that none escapes the
#     checks below by accident; ```text (or any other kind) marks a block that is not checked;
#   - ```yaml with a top-level `nodes:` is a graph: `gslift validate` must accept it. A first line
#     `# graphs/<path>.yaml` names the file it shows (it must exist) and places the block in that
#     folder of a copy of graphs/, so that `extends:` and relative paths resolve as they would
#     there; otherwise it is placed in graphs/;
#   - ```bash / ```sh / ```shell / ```console (only `$ ` lines) are commands. Every argument that
#     is a path into the repository (graphs/..., docs/..., bench/..., .ci/...) must exist. A
#     `gslift SUB` command must name a subcommand (`gslift SUB --help` succeeds); `gslift nodes
#     TYPE` must know TYPE; `gslift run|validate|sweep|batch GRAPH ...` must pass `gslift validate
#     GRAPH` with the command's --input, --seed and --set (a sweep's --grid contributes its first
#     value; an --input only where it exists, and then validate checks the capture too). Nothing
#     heavier runs: a few dozen starts of gslift, each answer asked once.
#   - every relative link of a page reaches a file, and docs/README.md links every page of docs/.
#
# usage: doc_blocks_test.sh [--expect-failures N] GSLIFT REPO_ROOT [FILE.md...]
# Without files it checks README.md, docs/*.md, graphs/README.md, bench/README.md and
# bench/*/README.md
# (CHANGELOG.md is a record of the past and may name what is gone). With --expect-failures it
# succeeds only when exactly N problems are found (the test of this test).
set -u
shopt -s nullglob
expect=""
if [ "${1:-}" = "--expect-failures" ]; then expect=$2; shift 2; fi
gslift=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
src=$(cd "$2" && pwd)
shift 2
default_set=""
if [ $# -gt 0 ]; then
  files=("$@")
else
  default_set=1
  files=("$src/README.md" "$src"/docs/*.md "$src/graphs/README.md" "$src/bench/README.md"
    "$src"/bench/*/README.md)
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src/graphs" "$tmp/graphs"
mkdir "$tmp/blocks"

failures=0
checks=0
# The answers of gslift per question (subcommand, node type, validate line): each process start
# loads the whole catalogue, and the pages ask the same questions many times.
declare -A answered
fail() {
  echo "FAIL $*"
  failures=$((failures + 1))
}

# Each block as blocks/N.txt, its file, line and info string in blocks/N.meta.
awk -v out="$tmp/blocks" '
  /^[ \t]*```/ {
    if (!inside) {
      inside = 1; n = sprintf("%04d", n + 1)
      indent = $0; sub(/```.*/, "", indent)
      info = $0; sub(/^[ \t]*```/, "", info); gsub(/[ \t]/, "", info)
      printf "%s\t%d\t%s\n", FILENAME, FNR, info > (out "/" n ".meta"); close(out "/" n ".meta")
      printf "" > (out "/" n ".txt")
    } else {
      inside = 0; close(out "/" n ".txt")
    }
    next
  }
  # A fence indented under a list item: its lines carry the same indentation.
  inside {
    if (substr($0, 1, length(indent)) == indent) $0 = substr($0, length(indent) + 1)
    print > (out "/" n ".txt")
  }
' "${files[@]}"

# A repository path that must exist: relative, under one of the repository's top folders, and no
# placeholder or shell syntax in it.
check_path() {
  local where=$1 token=$2
  case $token in
    *'$'* | *'*'* | *'{'* | *'<'* | *'...'*) return ;;
    graphs/* | docs/* | bench/* | tests/* | nodes/* | base/* | graph/* | runtime/* | report/* | \
      app/* | fuzz/* | .ci/* | README.md | CHANGELOG.md | CMakeLists.txt)
      checks=$((checks + 1))
      [ -e "$src/$token" ] || fail "$where: '$token' does not exist in the repository" ;;
  esac
}

check_graph_block() {
  local where=$1 block=$2 n=$3 header dir
  header=$(head -n 1 "$block" | sed -n 's|^# *\(graphs/[^ ]*\.yaml\).*|\1|p')
  dir="$tmp/graphs"
  if [ -n "$header" ]; then
    if [ ! -f "$src/$header" ]; then
      fail "$where: the graph block names $header, which does not exist"
    fi
    dir="$tmp/$(dirname "$header")"
    mkdir -p "$dir"
  fi
  local file="$dir/doc_block_$n.yaml"
  cp "$block" "$file"
  checks=$((checks + 1))
  local out
  if ! out=$(cd "$tmp" && "$gslift" validate "$file" 2>&1); then
    fail "$where: gslift validate rejects the graph block:"
    printf '%s\n' "$out" | sed "s|$file|$where|; s|^|    |"
  fi
}

# One simple command (no pipes or lists), its words as shell words.
check_command() {
  local where=$1 text=$2
  local -a w
  # xargs splits as the shell would (quotes, backslashes) without expanding anything.
  mapfile -t w < <(printf '%s\n' "$text" | xargs -n 1 printf '%s\n' 2>/dev/null)
  [ ${#w[@]} -eq 0 ] && return
  local i=0
  while [ $i -lt ${#w[@]} ]; do
    case ${w[$i]} in exec | time | env | sudo | *=*) i=$((i + 1)) ;; *) break ;; esac
  done
  w=("${w[@]:$i}")
  [ ${#w[@]} -eq 0 ] && return
  local t
  for t in "${w[@]:1}"; do check_path "$where" "$t"; done
  case ${w[0]} in
    gslift | ./build/gslift | build/gslift) ;;
    *) return ;;
  esac
  local sub=${w[1]:-}
  [ -z "$sub" ] && return
  case $sub in -*) return ;; esac
  checks=$((checks + 1))
  if [ -z "${answered[sub:$sub]:-}" ]; then
    "$gslift" "$sub" --help > /dev/null 2>&1 && answered[sub:$sub]=ok || answered[sub:$sub]=no
  fi
  if [ "${answered[sub:$sub]}" != ok ]; then
    fail "$where: 'gslift $sub' is not a gslift command"
    return
  fi
  local -a args=("${w[@]:2}")
  case $sub in
    nodes)
      if [ ${#args[@]} -gt 0 ]; then
        checks=$((checks + 1))
        local type=${args[0]}
        if [ -z "${answered[node:$type]:-}" ]; then
          "$gslift" nodes "$type" > /dev/null 2>&1 && answered[node:$type]=ok || answered[node:$type]=no
        fi
        [ "${answered[node:$type]}" = ok ] || fail "$where: 'gslift nodes $type': no such node type"
      fi ;;
    run | validate | sweep | batch)
      local graph="" j=0 a
      local -a opts=()
      while [ $j -lt ${#args[@]} ]; do
        a=${args[$j]}
        case $a in
          --seed | --set)
            opts+=("$a" "${args[$((j + 1))]:-}"); j=$((j + 2)); continue ;;
          --input)
            # validate --input opens the capture and checks what the graph needs of it: an input
            # that exists here (shared data, relative to the repository) is checked, a
            # placeholder (CAPTURE, <capture>) or a generated one (embedded:...) is left out.
            a=${args[$((j + 1))]:-}
            if [ -n "$a" ] && [ -e "$src/$a" ]; then opts+=(--input "$a"); fi
            j=$((j + 2)); continue ;;
          --grid)
            local g=${args[$((j + 1))]:-}
            opts+=(--set "${g%%,*}"); j=$((j + 2)); continue ;;
          --out | --threads | --log-level | --cache-dir | --cache-size | --seeds | --shard | \
            --discover | --jobs | --retries)
            j=$((j + 2)); continue ;;
          -*) j=$((j + 1)); continue ;;
          *.yaml) [ -z "$graph" ] && graph=$a ;;
        esac
        j=$((j + 1))
      done
      case $graph in graphs/*) ;; *) return ;; esac
      [ -f "$src/$graph" ] || return # reported by check_path
      checks=$((checks + 1))
      local question="validate:$graph ${opts[*]}" out
      if [ -z "${answered[$question]:-}" ]; then
        out=$(cd "$src" && "$gslift" validate "$graph" "${opts[@]}" 2>&1) &&
          answered[$question]=ok || answered[$question]=$out
      fi
      if [ "${answered[$question]}" != ok ]; then
        fail "$where: 'gslift validate $graph ${opts[*]}' fails:"
        printf '%s\n' "${answered[$question]}" | sed 's|^|    |'
      fi ;;
  esac
}

# The commands of a shell block: comments dropped, continued lines joined, lists and pipes split.
check_command_block() {
  local where=$1 block=$2 kind=$3
  awk -v console="$([ "$kind" = console ] && echo 1 || echo 0)" '
    function flush() { if (cmd != "") print start "\t" cmd; cmd = "" }
    {
      line = $0
      if (cmd == "") start = NR
      if (console && cmd == "") { if (line !~ /^\$ /) next; sub(/^\$ /, "", line) }
      # Split at unquoted ; && || | and drop an unquoted comment.
      out = ""; q = ""
      for (i = 1; i <= length(line); i++) {
        c = substr(line, i, 1)
        if (q != "") { out = out c; if (c == q) q = ""; continue }
        if (c == "\"" || c == "\047") { q = c; out = out c; continue }
        if (c == "#" && (i == 1 || substr(line, i - 1, 1) ~ /[ \t]/)) break
        if (c == ";" || c == "|" || c == "&") {
          if (c != ";" && substr(line, i + 1, 1) == c) i++
          out = out "\n"; continue
        }
        out = out c
      }
      sub(/[ \t]+$/, "", out)
      cont = (out ~ /\\$/) || (out ~ /\n$/)
      sub(/\\$/, "", out)
      n = split(out, parts, "\n")
      for (k = 1; k <= n; k++) {
        cmd = cmd parts[k]
        if (k < n) flush()
      }
      if (!cont) flush()
    }
    END { flush() }
  ' "$block" > "$block.commands"
  local file=${where%:*} first=${where##*:} offset c
  while IFS=$'\t' read -r offset c; do
    [ -n "${c// /}" ] && check_command "$file:$((first + offset))" "$c"
  done < "$block.commands"
}

# Relative links of the pages ([text](path), ![alt](path)) must reach a file.
for file in "${files[@]}"; do
  dir=$(dirname "$file")
  while IFS=: read -r line target; do
    target=${target#*](}
    target=${target%)}
    target=${target%%#*}
    case $target in "" | http://* | https://* | mailto:*) continue ;; esac
    checks=$((checks + 1))
    [ -e "$dir/$target" ] || fail "${file#"$src"/}:$line: the link '$target' reaches no file"
  done < <(grep -no '\]([^) ]*)' "$file")
done

# docs/README.md is the index: it links every page of docs/.
if [ -n "$default_set" ]; then
  for page in "$src"/docs/*.md; do
    name=$(basename "$page")
    [ "$name" = README.md ] && continue
    checks=$((checks + 1))
    grep -q "]($name)" "$src/docs/README.md" || fail "docs/README.md does not index docs/$name"
  done
fi

for meta in "$tmp"/blocks/*.meta; do
  n=$(basename "$meta" .meta)
  IFS=$'\t' read -r file line info < "$meta"
  where="${file#"$src"/}:$line"
  block="$tmp/blocks/$n.txt"
  case $info in
    "") fail "$where: fenced block without an info string (bash, yaml, text, ...)" ;;
    yaml) grep -q '^nodes:' "$block" && check_graph_block "$where" "$block" "$n" ;;
    bash | sh | shell | console) check_command_block "$where" "$block" "$info" ;;
  esac
done

echo "$checks checks, $failures problems"
if [ -n "$expect" ]; then
  [ "$failures" -eq "$expect" ] || { echo "expected $expect problems"; exit 1; }
  exit 0
fi
[ "$checks" -gt 0 ] || { echo "no block was checked"; exit 1; }
[ "$failures" -eq 0 ]
