#!/usr/bin/env bash
# bench/bad_input_probe.sh [BIN_DIR]
#
# Probes every program with bad input and checks the contract of docs/DESIGN.md §3.4 and §5:
# exit status 2, exactly one line on stderr, starting with "error: ", naming the file (its
# path) or the option (--name) that is wrong, and nothing left behind (no output file or
# folder, no half-written file, no .tmp-* file).
#
# It makes a scratch folder (mktemp -d, removed at the end; KEEP=1 keeps it), writes valid
# inputs there with the programs themselves (splat-demo, splat-render, a few iterations of
# splat-train, splat-convert, splat-eval), damages them with python3 (standard library only),
# checks that the valid ones are accepted ("controls"), then runs each bad case under
# `timeout` and compares a listing of the scratch folder before and after it.
#
# Output: one table line per case (class, case, exit code, verdict and reason, the error line
# cut to 120 characters), a summary per class, the totals, and the full record of each FAIL.
# Exit status 1 if any case (or control) fails, else 0. No network. About 300 cases, 3-4
# minutes on 2 cores: most of it is the programs' own start-up (~0.5 s each, their shared
# libraries). Environment: CASE_TIMEOUT (seconds per case, default 60; a case that runs longer
# is a FAIL, "hang"), KEEP=1 (keep the scratch folder, with each case's argv, stdout, stderr
# and listings under log/N/, to rerun a case by hand).
set -uo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BIN=${1:-$ROOT/build/bin}
BIN=$(cd "$BIN" 2>/dev/null && pwd) || { echo "no such folder: ${1:-$ROOT/build/bin}" >&2; exit 2; }
CASE_TIMEOUT=${CASE_TIMEOUT:-60}
for tool in splat-train splat-render splat-eval splat-viewer splat-grad splat-psnr splat-scene \
            splat-convert splat-process splat-demo; do
  [[ -x $BIN/$tool ]] || { echo "missing $BIN/$tool" >&2; exit 2; }
done
command -v python3 >/dev/null || { echo "python3 is needed to write the damaged files" >&2; exit 2; }

S=$(mktemp -d "${TMPDIR:-/tmp}/bad_input_probe.XXXXXX")
cleanup() {
  chmod -R u+rwX "$S" 2>/dev/null
  if [[ ${KEEP:-0} == 1 ]]; then echo "scratch folder kept: $S"; else rm -rf "$S"; fi
}
trap cleanup EXIT
IN=$S/in       # every input, valid and damaged
NEW=$S/new     # an output path that must never appear
LOG=$S/log     # per-case stdout/stderr and listings (not watched)
mkdir -p "$IN" "$LOG" "$S/cwd" "$S/ctl"
cd "$S/cwd" || exit 2                  # the programs run here (the viewer's P key writes here)
unset DISPLAY WAYLAND_DISPLAY          # no window may be needed to report bad input
IS_ROOT=0; [[ $(id -u) == 0 ]] && IS_ROOT=1

# ---------------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------------

die() { echo "setup failed: $*" >&2; exit 2; }

# setup TOOL ARGS...: a step that makes valid inputs; it must succeed.
setup() {
  local tool=$1; shift
  timeout 120 "$BIN/$tool" "$@" </dev/null >"$LOG/setup.out" 2>"$LOG/setup.err" ||
    die "$tool $* -> $(cat "$LOG/setup.err")"
}

# Everything under the scratch folder except the logs, one line each: TYPE<tab>PATH<tab>META,
# files with their size and modification time, so a created, removed or rewritten file shows.
snapshot() {
  find "$S" -mindepth 1 -path "$LOG" -prune -o \( -type d -printf 'd\t%p\t\n' \) -o \( -printf 'f\t%p\t%s %T@\n' \)
}

# Prints "created|changed|removed<tab>PATH" for each difference between two snapshots.
compare_snapshots() {
  awk -F'\t' 'NR == FNR { meta[$2] = $3; next }
               { seen[$2] = 1; if (!($2 in meta)) print "created\t" $2; else if (meta[$2] != $3) print "changed\t" $2 }
               END { for (p in meta) if (!(p in seen)) print "removed\t" p }' "$1" "$2" | LC_ALL=C sort
}

# Sets REPLY to TEXT with the scratch path written $S, cut to N characters.
shorten() { local t=${2//$S/\$S}; ((${#t} > $1)) && t="${t:0:$1-3}..."; REPLY=$t; }

N_CASES=0; N_FAIL=0; N_SKIP=0; N_CONTROL_FAIL=0; N_RERUN=0
declare -A CLASS_TOTAL=() CLASS_FAIL=()
CLASS_ORDER=()
FAIL_RECORDS=()
SKIPS=()

# table_line CLASS NAME EXIT VERDICT ERROR_LINE
table_line() {
  local c n v e
  shorten 24 "$1"; c=$REPLY; shorten 36 "$2"; n=$REPLY; shorten 48 "$4"; v=$REPLY; shorten 120 "$5"; e=$REPLY
  printf '%-24s %-36s %4s  %-48s %s\n' "$c" "$n" "$3" "$v" "$e"
}
table_line CLASS CASE EXIT VERDICT "ERROR LINE"
printf '%s\n' "$(printf -- '-%.0s' {1..200})"

# check CLASS NAME EXPECT TOOL ARGS...
#   Runs TOOL ARGS (no DISPLAY, stdin /dev/null, cwd a scratch folder, under timeout) and holds
#   it to the contract; EXPECT is the text (a path or --option) the error line must hold, or
#   several such texts separated by '|', any of which will do.
check() {
  local class=$1 name=$2 expect=$3 tool=$4; shift 4
  local dir="$LOG/$((++N_CASES))"
  mkdir "$dir"
  printf '%s\n' "$tool" "$@" >"$dir/argv"
  snapshot >"$dir/before"
  local rc tries=0
  while :; do
    timeout -k 5 "$CASE_TIMEOUT" "${AS_USER[@]}" "$BIN/$tool" "$@" </dev/null >"$dir/out" 2>"$dir/err"
    rc=$?
    # The binary missing or half-written (someone is rebuilding build/): wait, then run again.
    if ((rc == 126 || rc == 127)) && grep -q '^timeout: failed to run' "$dir/err" && ((tries++ < 3)); then
      wait_for_binary "$BIN/$tool"; N_RERUN=$((N_RERUN + 1)); continue
    fi
    break
  done
  snapshot >"$dir/after"
  judge "$class" "$name" "$expect" "$rc" "$dir" "$tool" "$@"
}

# wait_for_binary FILE: until FILE is executable and has not changed for 5 s (at most 5 minutes).
wait_for_binary() {
  local i
  for ((i = 0; i < 150; i++)); do
    [[ -x $1 ]] && (($(date +%s) - $(stat -c %Y "$1") >= 5)) && return
    sleep 2
  done
}

# judge CLASS NAME EXPECT RC DIR TOOL ARGS...: the verdict of a case that has run.
judge() {
  local class=$1 name=$2 expect=$3 rc=$4 dir=$5; shift 5
  local err=() reasons=() first="" all
  mapfile -t err <"$dir/err"
  ((${#err[@]})) && first=${err[0]}
  all=$(printf '%s\n' "${err[@]}")
  if ((rc == 124 || rc == 137)); then reasons+=("hang (killed after ${CASE_TIMEOUT}s)")
  elif ((rc > 128)); then reasons+=("crash (signal $((rc - 128)))")
  elif ((rc != 2)); then reasons+=("exit $rc")
  fi
  if ((${#err[@]} == 0)); then reasons+=("nothing on stderr")
  else
    ((${#err[@]} != 1)) && reasons+=("${#err[@]} stderr lines")
    [[ $first != "error: "* ]] && reasons+=("first line is not 'error: ...'")
    local alternatives named=0 one
    IFS='|' read -ra alternatives <<<"$expect"
    for one in "${alternatives[@]}"; do [[ $all == *"$one"* ]] && named=1; done
    ((named)) || { shorten 60 "$expect"; reasons+=("does not name ${REPLY//|/ or }"); }
    [[ $all =~ \[json\.exception|libpng|terminate\ called|Assertion|Sanitizer ]] && reasons+=("library text in stderr")
  fi
  # What appeared, changed or went away in the scratch folder.
  local created=() changed=() removed=() kind path
  while IFS=$'\t' read -r kind path; do
    case $kind in created) created+=("$path") ;; changed) changed+=("$path") ;; removed) removed+=("$path") ;; esac
  done < <(compare_snapshots "$dir/before" "$dir/after")
  local what more
  for what in created changed removed; do
    local -n list=$what
    ((${#list[@]})) || continue
    shorten 200 "${list[0]}"; more=""
    ((${#list[@]} > 1)) && more=" (+$((${#list[@]} - 1)) more)"
    reasons+=("${what/created/left behind}: $REPLY$more")
  done
  for path in "${created[@]}"; do chmod -R u+rwX "$path" 2>/dev/null; rm -rf "$path"; done

  if [[ -z ${CLASS_TOTAL[$class]+x} ]]; then CLASS_ORDER+=("$class"); CLASS_TOTAL[$class]=0; CLASS_FAIL[$class]=0; fi
  CLASS_TOTAL[$class]=$((CLASS_TOTAL[$class] + 1))
  local verdict="OK" reason=""
  if ((${#reasons[@]})); then
    verdict="FAIL"; N_FAIL=$((N_FAIL + 1)); CLASS_FAIL[$class]=$((CLASS_FAIL[$class] + 1))
    printf -v reason '%s; ' "${reasons[@]}"; reason=${reason%; }
    local cmd stderr_text
    printf -v cmd '%q ' "$@"; cmd="$BIN/${cmd% }"
    stderr_text=$(printf '      | %s\n' "${err[@]:0:20}")
    FAIL_RECORDS+=("$(printf '[%d] %s / %s\n    command: %s\n    exit:    %s\n    reason:  %s\n    stderr:\n%s' \
      "$N_CASES" "$class" "$name" "${cmd//$S/\$S}" "$rc" "$reason" "${stderr_text//$S/\$S}")")
    verdict="FAIL ($reason)"
  fi
  table_line "$class" "$name" "$rc" "$verdict" "$first"
}

# skip CLASS NAME WHY: a case that cannot be run here.
skip() {
  N_SKIP=$((N_SKIP + 1)); SKIPS+=("$1 / $2: $3")
  table_line "$1" "$2" "-" "SKIP ($3)" ""
}

# unreadable CLASS NAME FILE EXPECT TOOL ARGS...: FILE made unreadable (chmod 000) for the run.
# Root reads it all the same: as root the case runs as the user nobody (runuser), with the
# scratch folder opened to it for the run; without runuser it is skipped.
AS_USER=()
unreadable() {
  local class=$1 name=$2 file=$3; shift 3
  if ((IS_ROOT)) && ! command -v runuser >/dev/null; then
    skip "$class" "$name" "running as root without runuser: chmod 000 does not deny reads"; return
  fi
  chmod 000 "$file"
  if ((IS_ROOT)); then
    chmod -R a+rwX "$S"; chmod 000 "$file"
    AS_USER=(runuser -u nobody --)
  fi
  check "$class" "$name" "$@"
  AS_USER=()
  chmod u+rwX "$file"
}

# control NAME TOOL ARGS...: a valid call like those the cases damage; it must succeed.
control() {
  local name=$1 tool=$2; shift 2
  if timeout -k 5 "$CASE_TIMEOUT" "$BIN/$tool" "$@" </dev/null >"$LOG/control.out" 2>"$LOG/control.err"; then
    table_line control "$name" 0 "OK (valid input accepted)" ""
  else
    local rc=$?
    N_CONTROL_FAIL=$((N_CONTROL_FAIL + 1))
    table_line control "$name" "$rc" "FAIL (valid input refused: probe unreliable)" "$(head -n1 "$LOG/control.err")"
  fi
}

# ---------------------------------------------------------------------------------------------
# Valid inputs, made by the programs themselves
# ---------------------------------------------------------------------------------------------

setup splat-demo --out "$IN/demo" --gaussians 200 --views 4 --size 32      # model.ply (SH 1), cameras.json
setup splat-render --model "$IN/demo/model.ply" --cameras "$IN/demo/cameras.json" --out "$IN/ds/views" --threads 1
cp "$IN/demo/cameras.json" "$IN/ds/transforms_train.json"                  # a Blender folder
cp "$IN/demo/cameras.json" "$IN/ds/transforms_test.json"
setup splat-render --model "$IN/demo/model.ply" --cameras "$IN/demo/cameras.json" --out "$IN/ds_other/views" --threads 1 --bg black
cp "$IN/demo/cameras.json" "$IN/ds_other/transforms_train.json"            # same poses, other images
cp "$IN/demo/cameras.json" "$IN/ds_other/transforms_test.json"
echo '{"random_init_points": 300}' >"$IN/tiny_splat.json"
cat >"$IN/tiny_nerf.json" <<'EOF'
{"rays_per_batch": 64, "model": {"coarse": {"width": 8, "color_width": 8, "depth": 1, "position_frequencies": 2,
 "direction_frequencies": 1}, "fine": {"width": 8, "color_width": 8, "depth": 1, "skip_layer": -1,
 "position_frequencies": 2, "direction_frequencies": 1}, "coarse_samples": 8, "fine_samples": 4,
 "occupancy_resolution": 8}}
EOF
sed 's/"width": 8, "color_width": 8, "depth": 1, "position/"width": 16, "color_width": 8, "depth": 1, "position/' \
  "$IN/tiny_nerf.json" >"$IN/other_nerf.json"
setup splat-train --data "$IN/ds" --out "$IN/tr" --iters 10 --checkpoint-every 10 --threads 1 --quiet --config "$IN/tiny_splat.json"
setup splat-train --data "$IN/ds" --out "$IN/trn" --method nerf --iters 10 --checkpoint-every 10 --threads 1 --quiet --config "$IN/tiny_nerf.json"
setup splat-convert "$IN/demo/model.ply" "$IN/model.splat"
setup splat-convert "$IN/demo/model.ply" "$IN/model.spz"
setup splat-eval --data "$IN/ds" --out "$IN/ev" --methods splat --max-seconds 1 --threads 1 --quiet --splat-config "$IN/tiny_splat.json"
cp "$ROOT/scenes/models/simple.gltf" "$IN/simple.gltf" || die "no scenes/models/simple.gltf"

# ---------------------------------------------------------------------------------------------
# Damaged inputs (python3, standard library only)
# ---------------------------------------------------------------------------------------------

cat >"$S/gen.py" <<'PY'
import gzip, json, math, os, shutil, struct, sys, zlib

IN = sys.argv[1]
def P(*parts): return os.path.join(IN, *parts)
def rd(path):
    with open(path, 'rb') as f: return f.read()
def wr(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, 'wb') as f: f.write(data.encode() if isinstance(data, str) else data)
def wjson(path, obj): wr(path, json.dumps(obj, indent=1))
def put(data, at, piece):
    b = bytearray(data); b[at:at + len(piece)] = piece; return bytes(b)
F_NAN, F_INF = struct.pack('<f', float('nan')), struct.pack('<f', float('inf'))
JUNK = b'\x00JUNK\xff\x13'

def png(w, h, channels=3, value=128, header_size=None):
    kind = {1: 0, 2: 4, 3: 2, 4: 6}[channels]
    raw = b''.join(b'\0' + bytes([value]) * (w * channels) for _ in range(h))
    def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    W, H = header_size or (w, h)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', W, H, 8, kind, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))

# --- 3DGS PLY -------------------------------------------------------------------------------
base = rd(P('demo', 'model.ply'))
hend = base.index(b'end_header\n') + len(b'end_header\n')
props = [l.split()[2] for l in base[:hend].decode().splitlines() if l.startswith('property')]
body = base[hend:]
row_bytes = 4 * len(props)
rows = [list(struct.unpack_from('<%df' % len(props), body, i * row_bytes)) for i in range(len(body) // row_bytes)]

def vertex_ply(props, rows, fmt='binary_little_endian', count=None, types=None, extra=(), comments=0,
               text_rows=None):
    types = types or {}
    h = ['ply', 'format %s 1.0' % fmt] + ['comment padding line %d' % i for i in range(comments)]
    h.append('element vertex %s' % (len(rows) if count is None else count))
    h += ['property %s %s' % (types.get(p, 'float'), p) for p in props] + list(extra) + ['end_header']
    head = ('\n'.join(h) + '\n').encode()
    if fmt == 'ascii':
        return head + (text_rows or '\n'.join(' '.join(repr(v) for v in r) for r in rows) + '\n').encode()
    e = '>' if fmt == 'binary_big_endian' else '<'
    out = bytearray()
    for r in rows:
        for p, v in zip(props, r): out += struct.pack(e + {'float': 'f', 'double': 'd'}[types.get(p, 'float')], v)
    return head + bytes(out)

def without(names):
    keep = [i for i, p in enumerate(props) if p not in names]
    return [props[i] for i in keep], [[r[i] for i in keep] for r in rows]

wr(P('ply', 'valid_ascii.ply'), vertex_ply(props, rows, 'ascii'))
wr(P('ply', 'valid_big_endian.ply'), vertex_ply(props, rows, 'binary_big_endian'))
wr(P('ply', 'empty.ply'), b'')
wr(P('ply', 'bad_magic.ply'), b'plx' + base[3:])
wr(P('ply', 'cut_in_header.ply'), base[:60])
wr(P('ply', 'cut_mid_row.ply'), base[:hend + row_bytes + 10])
wr(P('ply', 'cut_last_byte.ply'), base[:-1])
wr(P('ply', 'trailing.ply'), base + JUNK)
wr(P('ply', 'count_huge.ply'), vertex_ply(props, rows, count=4000000000))
bad = [r[:] for r in rows]; bad[3][props.index('x')] = float('nan')
wr(P('ply', 'nan_x.ply'), vertex_ply(props, bad))
bad = [r[:] for r in rows]
for k in ('rot_0', 'rot_1', 'rot_2', 'rot_3'): bad[2][props.index(k)] = 0.0
wr(P('ply', 'zero_rotation.ply'), vertex_ply(props, bad))
wr(P('ply', 'f_rest_7.ply'), vertex_ply(*without({'f_rest_7', 'f_rest_8'})))
wr(P('ply', 'no_rot_3.ply'), vertex_ply(*without({'rot_3'})))
wr(P('ply', 'double_x.ply'), vertex_ply(props, rows, types={'x': 'double'}))
wr(P('ply', 'list_property.ply'), vertex_ply(props, rows, extra=['property list uchar float extra']))
text = '\n'.join(' '.join(repr(v) for v in r) for r in rows).replace(repr(rows[0][0]), 'abc', 1) + '\n'
wr(P('ply', 'ascii_word.ply'), vertex_ply(props, rows, 'ascii', text_rows=text))
text = '\n'.join(' '.join(repr(v) for v in r) for r in rows[:-1]) + '\n' + ' '.join(repr(v) for v in rows[-1][:5]) + '\n'
wr(P('ply', 'ascii_short_row.ply'), vertex_ply(props, rows, 'ascii', text_rows=text))
wr(P('ply', 'header_12000_lines.ply'), vertex_ply(props, rows, comments=12000))
wr(P('ply', 'unknown_format.ply'), vertex_ply(props, rows, fmt='binary_middle_endian'))
# A compressed PLY as SuperSplat / splat-transform write it: a chunk element, packed vertices.
chunk_props = ['min_x', 'min_y', 'min_z', 'max_x', 'max_y', 'max_z', 'min_scale_x', 'min_scale_y',
               'min_scale_z', 'max_scale_x', 'max_scale_y', 'max_scale_z', 'min_r', 'min_g', 'min_b',
               'max_r', 'max_g', 'max_b']
h = ['ply', 'format binary_little_endian 1.0', 'comment Generated by SuperSplat', 'element chunk 1']
h += ['property float ' + p for p in chunk_props] + ['element vertex 4']
h += ['property uint ' + p for p in ('packed_position', 'packed_rotation', 'packed_scale', 'packed_color')]
h += ['end_header']
wr(P('ply', 'compressed.ply'), ('\n'.join(h) + '\n').encode() +
   struct.pack('<18f', *([-1] * 3 + [1] * 3 + [-5] * 3 + [0] * 3 + [0] * 3 + [1] * 3)) +
   struct.pack('<16I', *range(1, 17)))
h = ['ply', 'format binary_little_endian 1.0', 'element vertex 3', 'property float x', 'property float y',
     'property float z', 'element face 1', 'property list uchar int vertex_indices', 'end_header']
wr(P('ply', 'mesh.ply'), ('\n'.join(h) + '\n').encode() + struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) +
   struct.pack('<B3i', 3, 0, 1, 2))
h = ['ply', 'format ascii 1.0', 'element vertex 3', 'property float x', 'property float y', 'property float z',
     'property uchar red', 'property uchar green', 'property uchar blue', 'end_header']
wr(P('ply', 'point_cloud.ply'), '\n'.join(h) + '\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n')
os.makedirs(P('ply', 'folder.ply'), exist_ok=True)

# --- .splat -----------------------------------------------------------------------------------
sp = rd(P('model.splat'))
wr(P('splat', 'empty.splat'), b'')
wr(P('splat', 'trailing.splat'), sp + JUNK)
wr(P('splat', 'cut.splat'), sp[:-5])
wr(P('splat', 'nan_mean.splat'), put(sp, 32 * 4, F_NAN))
wr(P('splat', 'zero_scale.splat'), put(sp, 32 * 6 + 12, struct.pack('<f', 0.0)))
wr(P('splat', 'zero_rotation.splat'), put(sp, 32 * 9 + 28, bytes([128, 128, 128, 128])))

# --- .spz -------------------------------------------------------------------------------------
gz = rd(P('model.spz'))
raw = gzip.decompress(gz)
magic, version, count, degree, frac, flags, reserved = struct.unpack_from('<IIIBBBB', raw)
def spz(header=None, payload=None):
    m = dict(magic=magic, version=version, count=count, degree=degree, frac=frac, flags=flags)
    m.update(header or {})
    head = struct.pack('<IIIBBBB', m['magic'], m['version'], m['count'], m['degree'], m['frac'], m['flags'], 0)
    return gzip.compress(head + (raw[16:] if payload is None else payload))
wr(P('spz', 'empty.spz'), b'')
wr(P('spz', 'not_gzip.spz'), raw)
wr(P('spz', 'cut_half.spz'), gz[:len(gz) // 2])
wr(P('spz', 'trailing.spz'), gz + JUNK)
wr(P('spz', 'two_gzip_members.spz'), gz + gz)
wr(P('spz', 'bad_magic.spz'), spz({'magic': 0x12345678}))
wr(P('spz', 'version_4.spz'), spz({'version': 4}))
wr(P('spz', 'sh_degree_5.spz'), spz({'degree': 5}))
wr(P('spz', 'count_huge.spz'), spz({'count': 1 << 25}))
wr(P('spz', 'inflated_short.spz'), spz(payload=raw[16:-10]))
wr(P('spz', 'inflated_long.spz'), spz(payload=raw[16:] + b'\0' * 10))

# --- .nerf ------------------------------------------------------------------------------------
nf = rd(P('trn', 'model.nerf'))
L = struct.unpack_from('<I', nf, 12)[0]
settings = json.loads(nf[16:16 + L])
def nerf(js): t = json.dumps(js).encode(); return nf[:12] + struct.pack('<I', len(t)) + t + nf[16 + L:]
arrays = 16 + L
wr(P('nerf', 'empty.nerf'), b'')
wr(P('nerf', 'bad_magic.nerf'), b'SPLATNRX' + nf[8:])
wr(P('nerf', 'version_2.nerf'), put(nf, 8, struct.pack('<I', 2)))
wr(P('nerf', 'settings_length_huge.nerf'), put(nf, 12, struct.pack('<I', 0xFFFFFFF0)))
wr(P('nerf', 'cut_in_settings.nerf'), nf[:16 + L // 2])
wr(P('nerf', 'cut_in_parameters.nerf'), nf[:arrays + (len(nf) - arrays) // 2])
wr(P('nerf', 'cut_last_byte.nerf'), nf[:-1])
wr(P('nerf', 'trailing.nerf'), nf + JUNK)
wr(P('nerf', 'nan_parameter.nerf'), put(nf, arrays + 8, F_NAN))
wr(P('nerf', 'count_huge.nerf'), put(nf, arrays, struct.pack('<Q', 1 << 40)))
wr(P('nerf', 'settings_malformed.nerf'), nf[:12] + struct.pack('<I', 9) + b'{"coarse"' + nf[16 + L:])
s = json.loads(json.dumps(settings)); s['coarse']['depth'] = 99
wr(P('nerf', 'settings_depth_99.nerf'), nerf(s))

# --- splat checkpoint -------------------------------------------------------------------------
ck = rd(P('tr', 'checkpoint.ckpt'))
HL = struct.unpack_from('<Q', ck, 12)[0]
head = json.loads(ck[20:20 + HL])
A = 20 + HL
def ckpt(h): t = json.dumps(h).encode(); return ck[:12] + struct.pack('<Q', len(t)) + t + ck[A:]
def array_offsets(data, start):
    at, out = start, []
    while at + 8 <= len(data):
        n = struct.unpack_from('<Q', data, at)[0]; out.append(at); at += 8 + 4 * n
    return out
offs = array_offsets(ck, A)
wr(P('ckpt', 'bad_magic.ckpt'), b'SPLATCKX' + ck[8:])
wr(P('ckpt', 'version_9.ckpt'), put(ck, 8, struct.pack('<I', 9)))
wr(P('ckpt', 'header_length_huge.ckpt'), put(ck, 12, struct.pack('<Q', 1 << 62)))
wr(P('ckpt', 'cut_in_header.ckpt'), ck[:20 + HL // 2])
wr(P('ckpt', 'cut_in_arrays.ckpt'), ck[:A + (len(ck) - A) // 2])
wr(P('ckpt', 'cut_last_byte.ckpt'), ck[:-1])
wr(P('ckpt', 'trailing.ckpt'), ck + JUNK)
wr(P('ckpt', 'nan_mean.ckpt'), put(ck, A + 8, F_NAN))
wr(P('ckpt', 'inf_adam_moment.ckpt'), put(ck, offs[5] + 8, F_INF))
wr(P('ckpt', 'count_huge.ckpt'), put(ck, A, struct.pack('<Q', 1 << 60)))
wr(P('ckpt', 'header_malformed.ckpt'), ck[:12] + struct.pack('<Q', 10) + b'{"config":' + ck[A:])
h = dict(head); h['iteration'] = -1; wr(P('ckpt', 'iteration_negative.ckpt'), ckpt(h))
h = dict(head); h['rng'] = 'garbage'; wr(P('ckpt', 'rng_garbage.ckpt'), ckpt(h))
os.makedirs(P('ckpt', 'folder_without_checkpoint'), exist_ok=True)
for name, metrics in (('resume_metrics_malformed', '{"history": ['), ('resume_metrics_shape', '{"history": 7}')):
    os.makedirs(P('ckpt', name), exist_ok=True)
    shutil.copy(P('tr', 'checkpoint.ckpt'), P('ckpt', name, 'checkpoint.ckpt'))
    wr(P('ckpt', name, 'metrics.json'), metrics)

# --- NeRF checkpoint --------------------------------------------------------------------------
nc = rd(P('trn', 'checkpoint.ckpt'))
wr(P('nckpt', 'bad_magic.ckpt'), b'SPLNRFCX' + nc[8:])
wr(P('nckpt', 'rng_length_huge.ckpt'), put(nc, 28, struct.pack('<Q', 1 << 40)))
wr(P('nckpt', 'cut_half.ckpt'), nc[:len(nc) // 2])
wr(P('nckpt', 'trailing.ckpt'), nc + JUNK)

# --- transforms JSON (--cameras) --------------------------------------------------------------
cams = json.loads(rd(P('demo', 'cameras.json')))
def tj(name, change=None, raw_text=None):
    if raw_text is not None: wr(P('tj', name), raw_text); return
    c = json.loads(json.dumps(cams)); change(c); wjson(P('tj', name), c)
tj('malformed.json', raw_text='{"frames": [')
tj('frames_not_array.json', lambda c: c.update(frames=7))
tj('frames_empty.json', lambda c: c.update(frames=[]))
tj('matrix_3x4.json', lambda c: c['frames'][1].update(transform_matrix=c['frames'][1]['transform_matrix'][:3]))
tj('matrix_scaled.json', lambda c: c['frames'][1].update(transform_matrix=[[2 * v for v in r[:3]] + [r[3]] for r in c['frames'][1]['transform_matrix'][:3]] + [[0, 0, 0, 1]]))
tj('no_matrix.json', lambda c: c['frames'][1].pop('transform_matrix'))
tj('number_overflow.json', raw_text=json.dumps(cams).replace('"fl_x": ', '"fl_x": 1e999, "x": ', 1))
tj('angle_zero.json', lambda c: ([c.pop(k, None) for k in ('fl_x', 'fl_y')], c.update(camera_angle_x=0)))
tj('fl_negative.json', lambda c: c.update(fl_x=-40))
tj('w_without_h.json', lambda c: (c.pop('h', None), c.update(w=32)))
tj('w_huge.json', lambda c: c.update(w=100000, h=100000))
def dup(c):  # one image, named with and without its extension: both views are named r_1
    c['frames'][0]['file_path'] = './r_1'; c['frames'][1]['file_path'] = './r_1.png'
tj('duplicate_names.json', dup)
def dup_same(c): c['frames'][2]['file_path'] = c['frames'][0]['file_path']
tj('duplicate_frame.json', dup_same)
os.makedirs(P('tj', 'folder.json'), exist_ok=True)

# --- Blender datasets (splat-train --data) ----------------------------------------------------
def blender(name, change=None):
    d = P('bl', name); shutil.copytree(P('ds'), d)
    if change: change(d)
    return d
def edit_json(path, change):
    c = json.loads(rd(path)); change(c); wjson(path, c)
blender('no_test_json', lambda d: os.remove(os.path.join(d, 'transforms_test.json')))
blender('train_malformed', lambda d: wr(os.path.join(d, 'transforms_train.json'), '{"frames": [{'))
blender('test_frames_object', lambda d: wr(os.path.join(d, 'transforms_test.json'), '{"frames": {}}'))
blender('train_nonrigid', lambda d: edit_json(os.path.join(d, 'transforms_train.json'),
        lambda c: c['frames'][2].update(transform_matrix=[[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 5], [0, 0, 0, 1]])))
blender('image_missing', lambda d: os.remove(os.path.join(d, 'views', 'view_1.png')))
view = rd(P('ds', 'views', 'view_1.png'))
blender('image_cut', lambda d: wr(os.path.join(d, 'views', 'view_1.png'), view[:len(view) // 2]))
blender('image_24px', lambda d: wr(os.path.join(d, 'views', 'view_1.png'), png(24, 24)))
blender('image_header_huge', lambda d: wr(os.path.join(d, 'views', 'view_1.png'), png(4, 4, header_size=(60000, 60000))))
blender('image_no_iend', lambda d: wr(os.path.join(d, 'views', 'view_1.png'), view[:-12]))
blender('test_duplicate_names', lambda d: edit_json(os.path.join(d, 'transforms_test.json'),
        lambda c: c['frames'][2].update(file_path=c['frames'][1]['file_path'])))
os.makedirs(P('bl', 'empty_folder'), exist_ok=True)
wr(P('bl', 'a_file'), 'not a folder')
# Another dataset with 3 training views (a checkpoint of 4 cannot resume on it).
blender('three_views', lambda d: edit_json(os.path.join(d, 'transforms_train.json'), lambda c: c['frames'].pop()))

# --- nerfstudio datasets ----------------------------------------------------------------------
ns = {'camera_model': 'OPENCV', 'fl_x': cams['fl_x'], 'fl_y': cams['fl_y'], 'cx': cams['cx'], 'cy': cams['cy'],
      'w': 32, 'h': 32, 'frames': [{'file_path': 'views/view_%d.png' % i, 'transform_matrix': f['transform_matrix']}
                                   for i, f in enumerate(cams['frames'])]}
pts = [(0.3 * math.cos(i), 0.3 * math.sin(i), 0.1 * (i % 7) - 0.3) for i in range(40)]
pc = ['ply', 'format ascii 1.0', 'element vertex %d' % len(pts), 'property float x', 'property float y',
      'property float z', 'property uchar red', 'property uchar green', 'property uchar blue', 'end_header']
pc = '\n'.join(pc) + '\n' + ''.join('%g %g %g 200 100 50\n' % p for p in pts)
def nerfstudio(name, change=None, files=None):
    d = P('ns', name); shutil.copytree(P('ds', 'views'), os.path.join(d, 'views'))
    c = json.loads(json.dumps(ns))
    if change: change(c)
    wjson(os.path.join(d, 'transforms.json'), c)
    for rel, data in (files or {}).items(): wr(os.path.join(d, rel), data)
    return d
nerfstudio('valid', lambda c: c.update(ply_file_path='sparse_pc.ply'), {'sparse_pc.ply': pc})
nerfstudio('fisheye', lambda c: c.update(camera_model='OPENCV_FISHEYE'))
nerfstudio('k3_nonzero', lambda c: c.update(k3=0.1))
nerfstudio('duplicate_names', lambda c: c['frames'][3].update(file_path='views/view_0.png'))
nerfstudio('ply_missing', lambda c: c.update(ply_file_path='sparse_pc.ply'))
nerfstudio('ply_garbage', lambda c: c.update(ply_file_path='sparse_pc.ply'), {'sparse_pc.ply': 'Mary had a lamb'})
nerfstudio('ply_count_huge', lambda c: c.update(ply_file_path='sparse_pc.ply'),
           {'sparse_pc.ply': pc.replace('element vertex %d' % len(pts), 'element vertex 900000000')})
nerfstudio('mask_missing', lambda c: c['frames'][1].update(mask_path='masks/view_1.png'))
nerfstudio('mask_8px', lambda c: c['frames'][1].update(mask_path='masks/view_1.png'), {'masks/view_1.png': png(8, 8, 1, 255)})

# --- COLMAP (text and binary) -----------------------------------------------------------------
def quaternion(R):  # rotation matrix -> (w, x, y, z)
    t = R[0][0] + R[1][1] + R[2][2]
    if t > 0:
        s = math.sqrt(t + 1) * 2; return ((s / 4), (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s)
    i = max(range(3), key=lambda k: R[k][k]); j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1 + R[i][i] - R[j][j] - R[k][k]) * 2
    q = [0, 0, 0, 0]; q[0] = (R[k][j] - R[j][k]) / s; q[1 + i] = s / 4
    q[1 + j] = (R[j][i] + R[i][j]) / s; q[1 + k] = (R[k][i] + R[i][k]) / s
    return tuple(q)
images = []
for i, f in enumerate(cams['frames']):
    M = f['transform_matrix']
    Rcw = [[M[r][0], -M[r][1], -M[r][2]] for r in range(3)]            # OpenGL -> OpenCV axes
    C = [M[r][3] for r in range(3)]
    Rwc = [[Rcw[c][r] for c in range(3)] for r in range(3)]
    t = [-sum(Rwc[r][c] * C[c] for c in range(3)) for r in range(3)]
    images.append((i + 1, quaternion(Rwc), t, 'view_%d.png' % i))
fx, fy, cx, cy = cams['fl_x'], cams['fl_y'], cams['cx'], cams['cy']
cam_line = '1 PINHOLE 32 32 %r %r %r %r' % (fx, fy, cx, cy)
def image_lines(imgs): return [('%d %r %r %r %r %r %r %r 1 %s' % ((i,) + q + tuple(t) + (n,))) for i, q, t, n in imgs]
point_lines = ['%d %g %g %g 200 100 50 0.5 1 0' % ((k + 1,) + p) for k, p in enumerate(pts)]
def colmap_text(name, cameras=None, imgs=None, points=None, drop=None):
    d = P('colmap', name); shutil.copytree(P('ds', 'views'), os.path.join(d, 'images'))
    s0 = os.path.join(d, 'sparse', '0')
    texts = {'cameras.txt': ['# Camera list', cameras or cam_line],
             'images.txt': ['# Image list'] + sum(([l, ''] for l in (imgs or image_lines(images))), []),
             'points3D.txt': ['# 3D point list'] + (point_lines if points is None else points)}
    for f, lines in texts.items():
        if f != drop: wr(os.path.join(s0, f), '\n'.join(lines) + '\n')
    return d
def with_image(k, **change):
    imgs = list(images); i, q, t, n = imgs[k]
    imgs[k] = (change.get('id', i), change.get('q', q), change.get('t', t), change.get('name', n))
    return image_lines(imgs)
colmap_text('text_valid')
colmap_text('text_model_fisheye', cameras='1 OPENCV_FISHEYE 32 32 %r %r %r %r 0 0 0 0' % (fx, fy, cx, cy))
colmap_text('text_params_short', cameras='1 PINHOLE 32 32 %r %r %r' % (fx, fy, cx))
colmap_text('text_camera_nan', cameras='1 PINHOLE 32 32 nan %r %r %r' % (fy, cx, cy))
colmap_text('text_distortion_extreme', cameras='1 OPENCV 32 32 %r %r %r %r 100 0 0 0' % (fx, fy, cx, cy))
colmap_text('text_unknown_camera', imgs=[l.replace(' 1 view_2', ' 7 view_2') for l in image_lines(images)])
colmap_text('text_zero_quaternion', imgs=with_image(2, q=(0, 0, 0, 0)))
colmap_text('text_duplicate_name', imgs=with_image(2, name='view_1.png'))
lines = image_lines(images); words = lines[2].split(); words[5] = 'abc'; lines[2] = ' '.join(words)
colmap_text('text_word_in_number', imgs=lines)
colmap_text('text_short_image_line', imgs=with_image(2)[:2] + ['3 1 0 0'] + with_image(2)[3:])
colmap_text('text_no_points', points=[])
colmap_text('text_no_images_txt', drop='images.txt')
colmap_text('text_photo_missing', imgs=with_image(2, name='nope.png'))
def colmap_binary(name, cameras=None, imgs=None, points=None, tail=None):
    d = P('colmap', name); shutil.copytree(P('ds', 'views'), os.path.join(d, 'images'))
    s0 = os.path.join(d, 'sparse', '0')
    cb = cameras if cameras is not None else struct.pack('<QiiQQ4d', 1, 1, 1, 32, 32, fx, fy, cx, cy)
    ib = struct.pack('<Q', len(images)) + b''.join(struct.pack('<I4d3dI', i, *q, *t, 1) + n.encode() + b'\0' + struct.pack('<Q', 0)
                                                 for i, q, t, n in images)
    pb = struct.pack('<Q', len(pts)) + b''.join(struct.pack('<Q3d3BdQii', k + 1, *p, 200, 100, 50, 0.5, 1, 1, 0)
                                               for k, p in enumerate(pts))
    files = {'cameras.bin': cb, 'images.bin': ib if imgs is None else imgs(ib), 'points3D.bin': pb if points is None else points(pb)}
    for f, data in files.items(): wr(os.path.join(s0, f), data + ((tail or {}).get(f, b'')))
    return d
colmap_binary('binary_valid')
colmap_binary('binary_cameras_trailing', tail={'cameras.bin': b'\0\0\0'})
colmap_binary('binary_images_cut', imgs=lambda b: b[:len(b) // 2])
colmap_binary('binary_points_count_huge', points=lambda b: struct.pack('<Q', 1 << 60) + b[8:])
colmap_binary('binary_name_unterminated', imgs=lambda b: b[:b.rindex(b'view_3.png') + 6])
colmap_binary('binary_no_cameras', cameras=struct.pack('<Q', 0))
colmap_binary('binary_width_huge', cameras=struct.pack('<QiiQQ4d', 1, 1, 1, 1 << 40, 32, fx, fy, cx, cy))

# --- training configs -------------------------------------------------------------------------
configs = {'malformed.json': '{"iterations": ', 'array_root.json': '[1]', 'unknown_key.json': '{"iteratons": 5}',
           'iterations_string.json': '{"iterations": "ten"}', 'sh_degree_9.json': '{"sh_degree": 9}',
           'batch_3.json': '{"batch": 3, "random_init_points": 300}',
           'strategy_official.json': '{"strategy": "official", "random_init_points": 300}',
           'near_beyond_far.json': '{"random_init_near": 20, "random_init_far": 10}',
           'nerf_depth_99.json': '{"model": {"coarse": {"depth": 99}}}'}
for name, text in configs.items(): wr(P('cfg', name), text)

# --- scene specs (splat-scene) ----------------------------------------------------------------
spec = {'gltf': 'simple.gltf', 'cameras': {'rig': 'orbit', 'radius': 3.5, 'elevation_deg': [10, 60], 'fov_deg': 40,
        'width': 16, 'height': 16, 'train': 1, 'test': 1}, 'lights': [{'type': 'directional',
        'direction': [-0.3, -1.0, -0.5], 'intensity': 2.0}], 'samples_per_pixel': 1}
os.makedirs(P('scene'), exist_ok=True); shutil.copy(P('simple.gltf'), P('scene', 'simple.gltf'))
def scene(name, change=None, raw_text=None):
    if raw_text is not None: wr(P('scene', name), raw_text); return
    s = json.loads(json.dumps(spec)); change and change(s); wjson(P('scene', name), s)
scene('valid.json')
scene('malformed.json', raw_text='{"gltf": "simple.gltf", "cameras": {')
scene('unknown_key.json', lambda s: s['cameras'].update(raduis=3))
scene('radius_huge.json', lambda s: s['cameras'].update(radius=1e7))
scene('width_zero.json', lambda s: s['cameras'].update(width=0))
scene('no_gltf_key.json', lambda s: s.pop('gltf'))
scene('gltf_missing.json', lambda s: s.update(gltf='missing.gltf'))
scene('gltf_garbage.json', lambda s: s.update(gltf='garbage.gltf'))
scene('gltf_obj.json', lambda s: s.update(gltf='simple.obj'))
scene('glb_cut.json', lambda s: s.update(gltf='cut.glb'))
scene('gltf_far_node.json', lambda s: s.update(gltf='far_node.gltf'))
scene('gltf_bad_index.json', lambda s: s.update(gltf='bad_buffer.gltf'))
wr(P('scene', 'garbage.gltf'), 'Mary had a little lamb')
shutil.copy(P('simple.gltf'), P('scene', 'simple.obj'))
wr(P('scene', 'cut.glb'), b'glTF' + struct.pack('<II', 2, 5000) + struct.pack('<II', 100, 0x4E4F534A) + b'{"asset":')
g = json.loads(rd(P('simple.gltf'))); g['nodes'][0]['translation'] = [1e7, 0, 0]; wjson(P('scene', 'far_node.gltf'), g)
g = json.loads(rd(P('simple.gltf'))); g['accessors'][0]['count'] = 10 ** 9; wjson(P('scene', 'bad_buffer.gltf'), g)

# --- images (splat-psnr), raw floats (splat-grad), result files (splat-eval --report) ----------
wr(P('img', 'a.png'), view)
wr(P('img', 'b.png'), rd(P('ds', 'views', 'view_2.png')))
wr(P('img', 'small.png'), png(24, 24))
wr(P('img', 'cut.png'), view[:len(view) // 2])
for d, names in (('dirA', ['view_0.png', 'view_1.png']), ('dirB', ['view_0.png']), ('dirC', ['view_0.png', 'view_1.png'])):
    for n in names: wr(P('img', d, n), view)
wr(P('img', 'dirC', 'view_1.png'), png(24, 24))
os.makedirs(P('img', 'dir_empty'), exist_ok=True)
wr(P('f32', 'w.f32'), b'\0' * (3 * 32 * 32 * 4))
wr(P('f32', 'w_short.f32'), b'\0' * (3 * 32 * 32 * 4 - 4))
wr(P('f32', 'w_nan.f32'), F_NAN * (3 * 32 * 32))
wr(P('f32', 'compare_short.f32'), b'\0' * 10)
results = json.loads(rd(P('ev', 'results.json')))
def report(name, files):
    os.makedirs(P('rep', name), exist_ok=True)
    for f, text in files.items(): wr(P('rep', name, f), text)
r = json.loads(json.dumps(results))
for m in r['methods']: m['history'] = []
report('empty_histories', {'results.json': json.dumps(r)})
report('nothing_scored', {'results.json': json.dumps({'methods': [{'method': 'splat', 'history': []},
                                                                 {'method': 'nerf', 'history': []}]})})
report('no_result_files', {})
report('results_malformed', {'results.json': '{"methods": ['})
r = json.loads(json.dumps(results)); r['methods'][0]['final']['psnr'] = 'high'
report('results_wrong_type', {'results.json': json.dumps(r)})
report('sweep_wrong_shape', {'sweep.json': '{"runs": 5}'})
r = json.loads(json.dumps(results)); del r['data']
report('results_without_data', {'results.json': json.dumps(r)})
report('results_folder', {}); os.makedirs(P('rep', 'results_folder', 'results.json'), exist_ok=True)
PY
python3 "$S/gen.py" "$IN" || die "writing the damaged inputs"

# A few more made with the shell: photo folders for splat-process, folders where files belong.
mkdir -p "$IN/photos/none" "$IN/photos/two" "$IN/photos/three" "$IN/photos/text_only" "$IN/photos/three_one_bad" "$S/out_exists"
for k in 0 1 2; do cp "$IN/ds/views/view_$k.png" "$IN/photos/three/p$k.png"; done
cp "$IN/img/a.png" "$IN/photos/two/p1.png"; cp "$IN/img/b.png" "$IN/photos/two/p2.png"
echo "notes" >"$IN/photos/text_only/readme.txt"
cp "$IN/img/a.png" "$IN/photos/three_one_bad/p1.png"; cp "$IN/img/b.png" "$IN/photos/three_one_bad/p2.png"
echo "Mary had a little lamb" >"$IN/photos/three_one_bad/p3.png"
echo "x" >"$S/out_exists/keep.txt"      # an existing, non-empty output folder
echo "a file" >"$IN/a_file"
mkdir -p "$IN/a_folder" "$IN/folder.mp4" "$IN/out.ply"

DS=$IN/ds; M=$IN/demo/model.ply; CAMS=$IN/demo/cameras.json; TJ=$IN/tj; W=$IN/f32/w.f32
# Models in training folders whose cameras_train.json (taken when no --cameras is given) is bad.
for kind in malformed frames_empty matrix_3x4 folder; do
  mkdir -p "$IN/beside_$kind"; cp "$M" "$IN/beside_$kind/model.ply"
  if [[ $kind == folder ]]; then mkdir "$IN/beside_$kind/cameras_train.json"
  else cp "$TJ/$kind.json" "$IN/beside_$kind/cameras_train.json"; fi
done
CK=$IN/tr/checkpoint.ckpt; NCK=$IN/trn/checkpoint.ckpt; NERF=$IN/trn/model.nerf
T=(--data "$DS" --out "$NEW" --iters 20 --threads 1 --quiet --test-every 0)   # splat-train, tiny
TC=("${T[@]}" --config "$IN/tiny_splat.json")
TN=(--data "$DS" --out "$NEW" --iters 20 --threads 1 --quiet --test-every 0 --method nerf --config "$IN/tiny_nerf.json")
R=(--model "$M" --cameras "$CAMS" --out "$NEW" --threads 1)                   # splat-render
RP=(--model "$M" --path orbit --frames 2 --width 16 --height 16 --out "$NEW" --threads 1)
G=(--model "$M" --cameras "$CAMS" --view 0 --width 32 --height 32 --bg white --weights "$W" --out "$NEW.f32")
E=(--data "$DS" --out "$NEW" --methods splat --max-seconds 1 --threads 1 --quiet --splat-config "$IN/tiny_splat.json")
V=(--width 64 --height 64)                                                    # splat-viewer

# ---------------------------------------------------------------------------------------------
# Controls: the valid inputs the cases damage are accepted
# ---------------------------------------------------------------------------------------------
control "render .ply" splat-render --model "$M" --cameras "$CAMS" --out "$S/ctl/r1" --threads 1
control "render .splat" splat-render --model "$IN/model.splat" --cameras "$CAMS" --out "$S/ctl/r2" --threads 1
control "render .spz" splat-render --model "$IN/model.spz" --cameras "$CAMS" --out "$S/ctl/r3" --threads 1
control "render .nerf" splat-render --model "$NERF" --cameras "$CAMS" --out "$S/ctl/r4" --threads 1 --width 8 --height 8
control "render ascii PLY" splat-render --model "$IN/ply/valid_ascii.ply" --cameras "$CAMS" --out "$S/ctl/r5" --threads 1
control "render big-endian PLY" splat-render --model "$IN/ply/valid_big_endian.ply" --cameras "$CAMS" --out "$S/ctl/r6" --threads 1
control "train on COLMAP text" splat-train --data "$IN/colmap/text_valid" --out "$S/ctl/t1" --iters 2 --threads 1 --quiet --config "$IN/tiny_splat.json"
control "train on COLMAP binary" splat-train --data "$IN/colmap/binary_valid" --out "$S/ctl/t2" --iters 2 --threads 1 --quiet --config "$IN/tiny_splat.json"
control "train on nerfstudio + PLY" splat-train --data "$IN/ns/valid" --out "$S/ctl/t3" --iters 2 --threads 1 --quiet --config "$IN/tiny_splat.json"
control "train --resume" splat-train --data "$DS" --out "$S/ctl/t4" --iters 12 --threads 1 --quiet --resume "$CK"
control "train nerf --resume" splat-train --data "$DS" --out "$S/ctl/t5" --iters 12 --threads 1 --quiet --method nerf --config "$IN/tiny_nerf.json" --resume "$NCK"
control "grad" splat-grad "${G[@]}" --out "$S/ctl/g.f32"
control "psnr" splat-psnr "$IN/img/a.png" "$IN/img/b.png"
control "scene render" splat-scene render "$IN/scene/valid.json" --out "$S/ctl/sc" --threads 1
control "eval --report" splat-eval --report --out "$IN/ev" --quiet
control "convert .ply -> .spz" splat-convert "$M" "$S/ctl/c.spz"

# ---------------------------------------------------------------------------------------------
# The cases: check CLASS NAME EXPECT TOOL ARGS...
# ---------------------------------------------------------------------------------------------
PLY=$IN/ply; SPL=$IN/splat; SPZ=$IN/spz; NF=$IN/nerf; CKD=$IN/ckpt; NCKD=$IN/nckpt
BL=$IN/bl; NS=$IN/ns; COL=$IN/colmap; CFG=$IN/cfg; SC=$IN/scene; IMG=$IN/img; REP=$IN/rep

# --- 3DGS PLY (splat-render --model) ---
check "empty file"          "ply: empty"                    "$PLY/empty.ply"            splat-render "${R[@]}" --model "$PLY/empty.ply"
check "wrong magic"         "ply: magic plx"                "$PLY/bad_magic.ply"        splat-render "${R[@]}" --model "$PLY/bad_magic.ply"
check "truncated file"      "ply: cut in header"            "$PLY/cut_in_header.ply"    splat-render "${R[@]}" --model "$PLY/cut_in_header.ply"
check "truncated file"      "ply: cut mid row"              "$PLY/cut_mid_row.ply"      splat-render "${R[@]}" --model "$PLY/cut_mid_row.ply"
check "truncated file"      "ply: cut last byte"            "$PLY/cut_last_byte.ply"    splat-render "${R[@]}" --model "$PLY/cut_last_byte.ply"
check "trailing bytes"      "ply: junk after vertices"      "$PLY/trailing.ply"         splat-render "${R[@]}" --model "$PLY/trailing.ply"
check "huge count"          "ply: vertex 4e9"               "$PLY/count_huge.ply"       splat-render "${R[@]}" --model "$PLY/count_huge.ply"
check "NaN/Inf"             "ply: NaN x"                    "$PLY/nan_x.ply"            splat-render "${R[@]}" --model "$PLY/nan_x.ply"
check "bad value"           "ply: zero quaternion"          "$PLY/zero_rotation.ply"    splat-render "${R[@]}" --model "$PLY/zero_rotation.ply"
check "bad header"          "ply: 7 f_rest"                 "$PLY/f_rest_7.ply"         splat-render "${R[@]}" --model "$PLY/f_rest_7.ply"
check "bad header"          "ply: no rot_3"                 "$PLY/no_rot_3.ply"         splat-render "${R[@]}" --model "$PLY/no_rot_3.ply"
check "bad header"          "ply: double x"                 "$PLY/double_x.ply"         splat-render "${R[@]}" --model "$PLY/double_x.ply"
check "bad header"          "ply: list property"            "$PLY/list_property.ply"    splat-render "${R[@]}" --model "$PLY/list_property.ply"
check "bad header"          "ply: 12000-line header"        "$PLY/header_12000_lines.ply" splat-render "${R[@]}" --model "$PLY/header_12000_lines.ply"
check "bad header"          "ply: unknown format"           "$PLY/unknown_format.ply"   splat-render "${R[@]}" --model "$PLY/unknown_format.ply"
check "bad value"           "ply ascii: word"               "$PLY/ascii_word.ply"       splat-render "${R[@]}" --model "$PLY/ascii_word.ply"
check "truncated file"      "ply ascii: short last row"     "$PLY/ascii_short_row.ply"  splat-render "${R[@]}" --model "$PLY/ascii_short_row.ply"
check "other layout PLY"    "ply: compressed (SuperSplat)"  "$PLY/compressed.ply"       splat-render "${R[@]}" --model "$PLY/compressed.ply"
check "other layout PLY"    "ply: mesh (x y z + face)"      "$PLY/mesh.ply"             splat-render "${R[@]}" --model "$PLY/mesh.ply"
check "other layout PLY"    "ply: point cloud"              "$PLY/point_cloud.ply"      splat-render "${R[@]}" --model "$PLY/point_cloud.ply"
check "wrong kind of file"  "ply: a folder"                 "$PLY/folder.ply"           splat-render "${R[@]}" --model "$PLY/folder.ply"
check "wrong kind of file"  "model: .obj extension"         "$IN/simple.gltf"           splat-render "${R[@]}" --model "$IN/simple.gltf"
unreadable "unreadable file" "ply: chmod 000" "$M" "$M" splat-render "${R[@]}"

# --- .splat ---
check "empty file"          "splat: empty"                  "$SPL/empty.splat"          splat-render "${R[@]}" --model "$SPL/empty.splat"
check "trailing bytes"      "splat: 7 junk bytes"           "$SPL/trailing.splat"       splat-render "${R[@]}" --model "$SPL/trailing.splat"
check "truncated file"      "splat: cut 5 bytes"            "$SPL/cut.splat"            splat-render "${R[@]}" --model "$SPL/cut.splat"
check "NaN/Inf"             "splat: NaN mean"               "$SPL/nan_mean.splat"       splat-render "${R[@]}" --model "$SPL/nan_mean.splat"
check "bad value"           "splat: zero scale"             "$SPL/zero_scale.splat"     splat-render "${R[@]}" --model "$SPL/zero_scale.splat"
check "bad value"           "splat: zero rotation"          "$SPL/zero_rotation.splat"  splat-render "${R[@]}" --model "$SPL/zero_rotation.splat"

# --- .spz ---
check "empty file"          "spz: empty"                    "$SPZ/empty.spz"            splat-render "${R[@]}" --model "$SPZ/empty.spz"
check "wrong magic"         "spz: not gzip"                 "$SPZ/not_gzip.spz"         splat-render "${R[@]}" --model "$SPZ/not_gzip.spz"
check "truncated file"      "spz: cut half"                 "$SPZ/cut_half.spz"         splat-render "${R[@]}" --model "$SPZ/cut_half.spz"
check "trailing bytes"      "spz: junk after gzip"          "$SPZ/trailing.spz"         splat-render "${R[@]}" --model "$SPZ/trailing.spz"
check "trailing bytes"      "spz: two gzip members"         "$SPZ/two_gzip_members.spz" splat-render "${R[@]}" --model "$SPZ/two_gzip_members.spz"
check "wrong magic"         "spz: magic"                    "$SPZ/bad_magic.spz"        splat-render "${R[@]}" --model "$SPZ/bad_magic.spz"
check "bad header"          "spz: version 4"                "$SPZ/version_4.spz"        splat-render "${R[@]}" --model "$SPZ/version_4.spz"
check "bad header"          "spz: SH degree 5"              "$SPZ/sh_degree_5.spz"      splat-render "${R[@]}" --model "$SPZ/sh_degree_5.spz"
check "huge count"          "spz: count 2^25"               "$SPZ/count_huge.spz"       splat-render "${R[@]}" --model "$SPZ/count_huge.spz"
check "truncated file"      "spz: inflated data short"      "$SPZ/inflated_short.spz"   splat-render "${R[@]}" --model "$SPZ/inflated_short.spz"
check "trailing bytes"      "spz: inflated data long"       "$SPZ/inflated_long.spz"    splat-render "${R[@]}" --model "$SPZ/inflated_long.spz"

# --- .nerf ---
check "empty file"          "nerf: empty"                   "$NF/empty.nerf"            splat-render "${R[@]}" --model "$NF/empty.nerf"
check "wrong magic"         "nerf: magic"                   "$NF/bad_magic.nerf"        splat-render "${R[@]}" --model "$NF/bad_magic.nerf"
check "bad header"          "nerf: version 2"               "$NF/version_2.nerf"        splat-render "${R[@]}" --model "$NF/version_2.nerf"
check "huge count"          "nerf: settings length 4e9"     "$NF/settings_length_huge.nerf" splat-render "${R[@]}" --model "$NF/settings_length_huge.nerf"
check "truncated file"      "nerf: cut in settings"         "$NF/cut_in_settings.nerf"  splat-render "${R[@]}" --model "$NF/cut_in_settings.nerf"
check "truncated file"      "nerf: cut in parameters"       "$NF/cut_in_parameters.nerf" splat-render "${R[@]}" --model "$NF/cut_in_parameters.nerf"
check "truncated file"      "nerf: cut last byte"           "$NF/cut_last_byte.nerf"    splat-render "${R[@]}" --model "$NF/cut_last_byte.nerf"
check "trailing bytes"      "nerf: junk at the end"         "$NF/trailing.nerf"         splat-render "${R[@]}" --model "$NF/trailing.nerf"
check "NaN/Inf"             "nerf: NaN parameter"           "$NF/nan_parameter.nerf"    splat-render "${R[@]}" --model "$NF/nan_parameter.nerf"
check "huge count"          "nerf: array count 2^40"        "$NF/count_huge.nerf"       splat-render "${R[@]}" --model "$NF/count_huge.nerf"
check "malformed JSON"      "nerf: settings JSON"           "$NF/settings_malformed.nerf" splat-render "${R[@]}" --model "$NF/settings_malformed.nerf"
check "option range"        "nerf: settings depth 99"       "$NF/settings_depth_99.nerf" splat-render "${R[@]}" --model "$NF/settings_depth_99.nerf"
check "nothing created on failure" "render bad.nerf --out NEW" "$NF/trailing.nerf"      splat-render --model "$NF/trailing.nerf" --cameras "$CAMS" --out "$NEW/sub"

# --- transforms JSON (splat-render --cameras) ---
check "malformed JSON"      "cameras: unterminated"         "$TJ/malformed.json"        splat-render "${R[@]}" --cameras "$TJ/malformed.json"
check "malformed JSON"      "cameras: 1e999"                "$TJ/number_overflow.json"  splat-render "${R[@]}" --cameras "$TJ/number_overflow.json"
check "JSON of wrong shape" "cameras: frames 7"             "$TJ/frames_not_array.json" splat-render "${R[@]}" --cameras "$TJ/frames_not_array.json"
check "JSON of wrong shape" "cameras: frames []"            "$TJ/frames_empty.json"     splat-render "${R[@]}" --cameras "$TJ/frames_empty.json"
check "JSON of wrong shape" "cameras: matrix 3x4"           "$TJ/matrix_3x4.json"       splat-render "${R[@]}" --cameras "$TJ/matrix_3x4.json"
check "bad value"           "cameras: matrix scaled x2"     "$TJ/matrix_scaled.json"    splat-render "${R[@]}" --cameras "$TJ/matrix_scaled.json"
check "JSON of wrong shape" "cameras: no transform_matrix"  "$TJ/no_matrix.json"        splat-render "${R[@]}" --cameras "$TJ/no_matrix.json"
check "bad value"           "cameras: camera_angle_x 0"     "$TJ/angle_zero.json"       splat-render "${R[@]}" --cameras "$TJ/angle_zero.json"
check "bad value"           "cameras: fl_x -40"             "$TJ/fl_negative.json"      splat-render "${R[@]}" --cameras "$TJ/fl_negative.json"
check "bad value"           "cameras: w without h"          "$TJ/w_without_h.json"      splat-render "${R[@]}" --cameras "$TJ/w_without_h.json"
check "bad value"           "cameras: w 100000"             "$TJ/w_huge.json"           splat-render "${R[@]}" --cameras "$TJ/w_huge.json"
check "duplicate output names" "render: frames r_1, r_1.png" "$TJ/duplicate_names.json"  splat-render "${R[@]}" --cameras "$TJ/duplicate_names.json"
check "duplicate output names" "render: one frame twice"    "$TJ/duplicate_frame.json"  splat-render "${R[@]}" --cameras "$TJ/duplicate_frame.json"
check "wrong kind of file"  "cameras: a folder"             "$TJ/folder.json"           splat-render "${R[@]}" --cameras "$TJ/folder.json"
check "missing file"        "cameras: missing"              "$TJ/missing.json"          splat-render "${R[@]}" --cameras "$TJ/missing.json"
unreadable "unreadable file" "cameras: chmod 000" "$CAMS" "$CAMS" splat-render "${R[@]}"

# --- splat-render options ---
check "option range"        "render --width 0 --height 0"   "--width"    splat-render "${R[@]}" --width 0 --height 0
check "option range"        "render --height abc"           "--height"   splat-render "${R[@]}" --width 8 --height abc
check "option range"        "render --sh-degree 9"          "--sh-degree" splat-render "${R[@]}" --sh-degree 9
check "option range"        "render --bench -1"             "--bench"    splat-render "${R[@]}" --bench -1
check "option range"        "render --threads 0"            "--threads"  splat-render "${R[@]}" --threads 0
check "option range"        "render --bg 5,5,5"             "--bg"       splat-render "${R[@]}" --bg 5,5,5
check "option range"        "render --frames 0"             "--frames"   splat-render "${RP[@]}" --frames 0
check "option range"        "render --fps 0"                "--fps"      splat-render "${RP[@]}" --video "$NEW.mp4" --fps 0
check "option range"        "render --video .avi"           "--video|$NEW.avi"    splat-render "${RP[@]}" --video "$NEW.avi"
check "option range"        "render --video odd width"      "--width"    splat-render "${RP[@]}" --video "$NEW.mp4" --width 15
check "option conflict"     "render --bench with --path"    "--bench"    splat-render "${RP[@]}" --bench 2
check "option conflict"     "render interpolate, no --cameras" "--cameras" splat-render "${RP[@]}" --path interpolate
check "option conflict"     "render --path, no --out/--video" "--out"    splat-render --model "$M" --path orbit --frames 2
check "unknown option"      "render --colour"               "--colour"   splat-render "${R[@]}" --colour red
check "unknown option"      "render flag with value"        "--png16"    splat-render "${R[@]}" --png16=yes
check "missing value"       "render --out (no value)"       "--out"      splat-render --model "$M" --cameras "$CAMS" --out
check "missing required option" "render without --model"   "--model"    splat-render --cameras "$CAMS" --out "$NEW"
check "missing required option" "render without --cameras" "--cameras"  splat-render --model "$M" --out "$NEW"
check "wrong kind of file"  "render --out is a file"        "$IN/a_file" splat-render "${R[@]}" --out "$IN/a_file"
check "nothing created on failure" "render frames ok, --video is a folder" "$IN/folder.mp4" splat-render "${RP[@]}" --video "$IN/folder.mp4"
for kind in malformed frames_empty matrix_3x4; do
  check "cameras beside the model" "render orbit, $kind cameras_train.json beside" "$IN/beside_$kind/cameras_train.json" \
    splat-render --model "$IN/beside_$kind/model.ply" --path orbit --frames 2 --width 16 --height 16 --out "$NEW"
  check "cameras beside the model" "viewer, $kind cameras_train.json beside" "$IN/beside_$kind/cameras_train.json" \
    splat-viewer "$IN/beside_$kind/model.ply" "${V[@]}"
done
check "cameras beside the model" "render interpolate, cameras_train.json a folder" "--cameras" \
  splat-render --model "$IN/beside_folder/model.ply" --path interpolate --frames 2 --width 16 --height 16 --out "$NEW"

# --- splat-viewer (DISPLAY unset: bad input must be reported before any window) ---
check "no display"          "viewer valid model, no DISPLAY" "DISPLAY"   splat-viewer "$M" "${V[@]}"
check "NaN/Inf"             "viewer: NaN PLY"               "$PLY/nan_x.ply"            splat-viewer "$PLY/nan_x.ply" "${V[@]}"
check "other layout PLY"    "viewer: compressed PLY"        "$PLY/compressed.ply"       splat-viewer "$PLY/compressed.ply" "${V[@]}"
check "trailing bytes"      "viewer: .spz junk"             "$SPZ/trailing.spz"         splat-viewer "$SPZ/trailing.spz" "${V[@]}"
check "trailing bytes"      "viewer: .nerf junk"            "$NF/trailing.nerf"         splat-viewer "$NF/trailing.nerf" "${V[@]}"
check "missing file"        "viewer: second model missing"  "$PLY/missing.ply"          splat-viewer "$M" "$PLY/missing.ply" "${V[@]}"
check "unexpected argument" "viewer: three models"          "3"                         splat-viewer "$M" "$M" "$M" "${V[@]}"
check "missing required option" "viewer: no model"          "model"                     splat-viewer "${V[@]}"
check "malformed JSON"      "viewer: --cameras malformed"   "$TJ/malformed.json"        splat-viewer "$M" "${V[@]}" --cameras "$TJ/malformed.json"
check "option range"        "viewer --view 99"              "--view"     splat-viewer "$M" "${V[@]}" --cameras "$CAMS" --view 99
check "option conflict"     "viewer --view without --cameras" "--view"   splat-viewer "$M" "${V[@]}" --view 1
check "option range"        "viewer --width 8"              "--width"    splat-viewer "$M" --width 8 --height 64
check "option range"        "viewer --height 9000"          "--height"   splat-viewer "$M" --width 64 --height 9000
check "option range"        "viewer --fps 0"                "--fps"      splat-viewer "$M" "${V[@]}" --fps 0
check "option range"        "viewer --sh-degree 9"          "--sh-degree" splat-viewer "$M" "${V[@]}" --sh-degree 9
check "option range"        "viewer --bg 5,5,5"             "--bg"       splat-viewer "$M" "${V[@]}" --bg 5,5,5
check "option range"        "viewer --bench-orbit -1"       "--bench-orbit" splat-viewer "$M" "${V[@]}" --bench-orbit -1
check "option conflict"     "viewer --screenshot-overlay alone" "--screenshot" splat-viewer "$M" "${V[@]}" --screenshot-overlay
check "missing file"        "viewer --watch missing folder" "$IN/nowhere" splat-viewer --watch "$IN/nowhere" "${V[@]}"
check "option conflict"     "viewer --watch with a model"   "--watch"    splat-viewer --watch "$IN/tr" "$M" "${V[@]}"
check "unknown option"      "viewer --fullscreen"           "--fullscreen" splat-viewer "$M" "${V[@]}" --fullscreen

# --- splat-grad ---
check "option range"        "grad --view 4 (of 4)"          "--view"     splat-grad "${G[@]}" --view 4
check "option range"        "grad --width 0"                "--width"    splat-grad "${G[@]}" --width 0
check "option range"        "grad --height x"               "--height"   splat-grad "${G[@]}" --height x
check "option range"        "grad --bench -1"               "--bench"    splat-grad "${G[@]}" --bench -1
check "option range"        "grad --bg 5,5,5"               "--bg"       splat-grad "${G[@]}" --bg 5,5,5
check "option range"        "grad --alpha-clamp-gradient x" "--alpha-clamp-gradient" splat-grad "${G[@]}" --alpha-clamp-gradient sideways
check "missing required option" "grad without --bg"         "--bg"       splat-grad --model "$M" --cameras "$CAMS" --view 0 --width 32 --height 32 --weights "$W" --out "$NEW.f32"
check "missing required option" "grad without --weights"    "--weights"  splat-grad --model "$M" --cameras "$CAMS" --view 0 --width 32 --height 32 --bg white --out "$NEW.f32"
check "truncated file"      "grad: weights 4 bytes short"   "$IN/f32/w_short.f32"  splat-grad "${G[@]}" --weights "$IN/f32/w_short.f32"
check "NaN/Inf"             "grad: weights all NaN"         "$IN/f32/w_nan.f32"    splat-grad "${G[@]}" --weights "$IN/f32/w_nan.f32"
check "truncated file"      "grad: --compare wrong size"    "$IN/f32/compare_short.f32" splat-grad "${G[@]}" --compare "$IN/f32/compare_short.f32"
check "wrong kind of file"  "grad: model .nerf"             "$NERF"                splat-grad "${G[@]}" --model "$NERF"
check "nothing created on failure" "grad: --image is a folder" "$IN/a_folder"  splat-grad "${G[@]}" --image "$IN/a_folder"
check "unknown option"      "grad --weight (typo)"          "--weight"   splat-grad "${G[@]}" --weight "$W"

# --- splat-psnr ---
check "option range"        "psnr --bg 5,5,5"               "--bg"       splat-psnr "$IMG/a.png" "$IMG/b.png" --bg 5,5,5
check "mismatched sizes"    "psnr 32px vs 24px"             "$IMG/small.png" splat-psnr "$IMG/a.png" "$IMG/small.png"
check "mismatched sizes"    "psnr folders, one image 24px"  "view_1.png" splat-psnr "$IMG/dirA" "$IMG/dirC"
check "truncated file"      "psnr: PNG cut in half"         "$IMG/cut.png"   splat-psnr "$IMG/cut.png" "$IMG/a.png"
check "missing file"        "psnr: missing image"           "$IMG/none.png"  splat-psnr "$IMG/a.png" "$IMG/none.png"
check "wrong kind of file"  "psnr: folder vs file"          "$IMG/a.png"     splat-psnr "$IMG/dirA" "$IMG/a.png"
check "missing file"        "psnr: folder B lacks an image" "view_1.png"     splat-psnr "$IMG/dirA" "$IMG/dirB"
check "empty file"          "psnr: folders without PNGs"    "$IMG/dir_empty" splat-psnr "$IMG/dir_empty" "$IMG/dir_empty"
check "missing required option" "psnr: one argument"        "expected two" splat-psnr "$IMG/a.png"
check "unexpected argument" "psnr: three arguments"         "expected two" splat-psnr "$IMG/a.png" "$IMG/b.png" "$IMG/a.png"
check "unknown option"      "psnr --background"             "--background" splat-psnr "$IMG/a.png" "$IMG/b.png" --background white
unreadable "unreadable file" "psnr: chmod 000" "$IMG/b.png" "$IMG/b.png" splat-psnr "$IMG/a.png" "$IMG/b.png"

# --- splat-convert ---
check "missing required option" "convert: one argument"    "expected IN and OUT"        splat-convert "$M"
check "unexpected argument" "convert: three arguments"      "expected IN and OUT"   splat-convert "$M" "$NEW.splat" "$NEW.spz"
check "wrong kind of file"  "convert: output .obj"          "$NEW.obj"   splat-convert "$M" "$NEW.obj"
check "wrong kind of file"  "convert: input .gltf"          "$IN/simple.gltf" splat-convert "$IN/simple.gltf" "$NEW.ply"
check "wrong kind of file"  "convert: output is a folder"   "$IN/out.ply" splat-convert "$M" "$IN/out.ply"
check "option range"        "convert --spz-sh-bits 0,6"     "--spz-sh-bits" splat-convert "$M" "$NEW.spz" --spz-sh-bits 0,6
check "option range"        "convert --spz-sh-bits x,y"     "--spz-sh-bits" splat-convert "$M" "$NEW.spz" --spz-sh-bits x,y
check "trailing bytes"      "convert: .splat junk"          "$SPL/trailing.splat" splat-convert "$SPL/trailing.splat" "$NEW.ply"
check "other layout PLY"    "convert: compressed PLY"       "$PLY/compressed.ply" splat-convert "$PLY/compressed.ply" "$NEW.spz"
check "nothing created on failure" "convert into a new folder" "$PLY/trailing.ply" splat-convert "$PLY/trailing.ply" "$NEW/m.spz"
check "unknown option"      "convert --sh-bits"             "--sh-bits"  splat-convert "$M" "$NEW.spz" --sh-bits 6,6

# --- splat-demo ---
check "option range"        "demo --gaussians 0"            "--gaussians" splat-demo --out "$NEW" --gaussians 0
check "option range"        "demo --gaussians 10000001"     "--gaussians" splat-demo --out "$NEW" --gaussians 10000001
check "option range"        "demo --gaussians 0x10"         "--gaussians" splat-demo --out "$NEW" --gaussians 0x10
check "option range"        "demo --views 0"                "--views"    splat-demo --out "$NEW" --views 0
check "option range"        "demo --size 0"                 "--size"     splat-demo --out "$NEW" --size 0
check "option range"        "demo --size 99999999999"       "--size"     splat-demo --out "$NEW" --size 99999999999
check "missing required option" "demo without --out"        "--out"      splat-demo --gaussians 10
check "wrong kind of file"  "demo --out is a file"          "$IN/a_file" splat-demo --out "$IN/a_file" --gaussians 10
check "unknown option"      "demo --count"                  "--count"    splat-demo --out "$NEW" --count 10

# --- splat-scene ---
check "malformed JSON"      "scene: spec unterminated"      "$SC/malformed.json"         splat-scene render "$SC/malformed.json" --out "$NEW"
check "JSON of wrong shape" "scene: cameras.raduis"         "$SC/unknown_key.json"       splat-scene render "$SC/unknown_key.json" --out "$NEW"
check "JSON of wrong shape" "scene: no gltf key"            "$SC/no_gltf_key.json"       splat-scene render "$SC/no_gltf_key.json" --out "$NEW"
check "bad value"           "scene: radius 1e7"             "$SC/radius_huge.json"       splat-scene render "$SC/radius_huge.json" --out "$NEW"
check "bad value"           "scene: width 0"                "$SC/width_zero.json"        splat-scene render "$SC/width_zero.json" --out "$NEW"
check "missing file"        "scene: glTF missing"           "$SC/missing.gltf"           splat-scene render "$SC/gltf_missing.json" --out "$NEW"
check "malformed JSON"      "scene: glTF prose"             "$SC/garbage.gltf"           splat-scene render "$SC/gltf_garbage.json" --out "$NEW"
check "wrong kind of file"  "scene: glTF named .obj"        "simple.obj"                 splat-scene render "$SC/gltf_obj.json" --out "$NEW"
check "truncated file"      "scene: .glb cut"               "$SC/cut.glb"                splat-scene render "$SC/glb_cut.json" --out "$NEW"
check "bad value"           "scene: glTF node at 1e7"       "$SC/far_node.gltf"          splat-scene render "$SC/gltf_far_node.json" --out "$NEW"
check "huge count"          "scene: glTF accessor count 1e9" "$SC/bad_buffer.gltf"       splat-scene render "$SC/gltf_bad_index.json" --out "$NEW"
check "option range"        "scene --threads 0"             "--threads"  splat-scene render "$SC/valid.json" --out "$NEW" --threads 0
check "missing required option" "scene without --out"       "--out"      splat-scene render "$SC/valid.json"
check "unexpected argument" "scene: verb draw"              "draw|render SCENE.json"       splat-scene draw "$SC/valid.json" --out "$NEW"
check "wrong kind of file"  "scene: --out is a file"        "$IN/a_file" splat-scene render "$SC/valid.json" --out "$IN/a_file"

# --- splat-process (must fail before COLMAP runs) ---
check "missing file"        "process --images missing"      "$IN/nowhere"           splat-process --images "$IN/nowhere" --out "$NEW"
check "empty file"          "process --images empty"        "$IN/photos/none"       splat-process --images "$IN/photos/none" --out "$NEW"
check "bad value"           "process: 2 photos"             "$IN/photos/two"        splat-process --images "$IN/photos/two" --out "$NEW"
check "wrong kind of file"  "process: no photos, a .txt"    "$IN/photos/text_only"  splat-process --images "$IN/photos/text_only" --out "$NEW"
check "nothing created on failure" "process: one photo is text" "p3.png"            splat-process --images "$IN/photos/three_one_bad" --out "$NEW" --threads 1
check "missing file"        "process --video missing"       "$IN/none.mp4"          splat-process --video "$IN/none.mp4" --out "$NEW"
check "wrong kind of file"  "process --out not empty"       "$S/out_exists"         splat-process --images "$IN/photos/three" --out "$S/out_exists"
check "wrong kind of file"  "process --out a file"          "$IN/a_file"            splat-process --images "$IN/photos/three" --out "$IN/a_file"
check "option range"        "process --frames 0"            "--frames"    splat-process --video "$IN/none.mp4" --out "$NEW" --frames 0
check "option range"        "process --max-size -1"         "--max-size"  splat-process --images "$IN/photos/three" --out "$NEW" --max-size -1
check "option range"        "process --threads 0"           "--threads"   splat-process --images "$IN/photos/three" --out "$NEW" --threads 0
check "option range"        "process --matcher fuzzy"       "--matcher"   splat-process --images "$IN/photos/three" --out "$NEW" --matcher fuzzy
check "option conflict"     "process --images and --video"  "--video"     splat-process --images "$IN/photos/three" --video "$IN/none.mp4" --out "$NEW"
check "missing required option" "process without --out"     "--out"       splat-process --images "$IN/photos/two"

# --- splat-train: options ---
check "option range"        "train --iters 0"               "--iters"    splat-train "${TC[@]}" --iters 0
check "option range"        "train --max-seconds 0"         "--max-seconds" splat-train "${TC[@]}" --max-seconds 0
check "option range"        "train --threads 0"             "--threads"  splat-train "${TC[@]}" --threads 0
check "option range"        "train --seed -1"               "--seed"     splat-train "${TC[@]}" --seed -1
check "option range"        "train --downscale 0"           "--downscale" splat-train "${TC[@]}" --downscale 0
check "option range"        "train --train-views 99 (of 4)" "--train-views" splat-train "${TC[@]}" --train-views 99
check "option range"        "train --holdout-every -1"      "--holdout-every" splat-train "${TC[@]}" --holdout-every -1
check "option conflict"     "train --holdout-every on Blender" "--holdout-every|$DS" splat-train "${TC[@]}" --holdout-every 3
check "option range"        "train --max-gaussians 0"       "--max-gaussians" splat-train "${TC[@]}" --max-gaussians 0
check "option range"        "train --batch 0"               "--batch"    splat-train "${TC[@]}" --batch 0
check "option conflict"     "train --batch 3, --iters 20"   "--batch"    splat-train "${TC[@]}" --batch 3
check "option range"        "train --snapshot-every 0"      "--snapshot-every" splat-train "${TC[@]}" --snapshot-every 0
check "option range"        "train --test-every -1"         "--test-every" splat-train "${TC[@]}" --test-every -1
check "option range"        "train --checkpoint-every -1"   "--checkpoint-every" splat-train "${TC[@]}" --checkpoint-every -1
check "option range"        "train --bg red"                "--bg"       splat-train "${TC[@]}" --bg red
check "option range"        "train --method gauss"          "--method"   splat-train "${TC[@]}" --method gauss
check "option range"        "train --strategy greedy"       "--strategy" splat-train "${TC[@]}" --strategy greedy
check "option conflict"     "train nerf --max-gaussians"    "--max-gaussians" splat-train "${TN[@]}" --max-gaussians 100
check "option conflict"     "train --batch 2 --refine-poses" "--batch"   splat-train "${TC[@]}" --batch 2 --refine-poses
check "unknown option"      "train --iterations"            "--iterations" splat-train "${TC[@]}" --iterations 5
check "missing value"       "train --iters (no value)"      "--iters"    splat-train --data "$DS" --out "$NEW" --iters
check "missing required option" "train without --data"      "--data"     splat-train --out "$NEW" --iters 20
check "missing required option" "train without --out"       "--out"      splat-train --data "$DS" --iters 20
check "wrong kind of file"  "train --out is a file"         "$IN/a_file" splat-train "${TC[@]}" --out "$IN/a_file"

# --- splat-train: configs ---
check "malformed JSON"      "config: unterminated"          "$CFG/malformed.json"          splat-train "${T[@]}" --config "$CFG/malformed.json"
check "JSON of wrong shape" "config: array root"            "$CFG/array_root.json"         splat-train "${T[@]}" --config "$CFG/array_root.json"
check "JSON of wrong shape" "config: unknown key"           "$CFG/unknown_key.json"        splat-train "${T[@]}" --config "$CFG/unknown_key.json"
check "JSON of wrong shape" "config: iterations \"ten\""    "$CFG/iterations_string.json"  splat-train "${T[@]}" --config "$CFG/iterations_string.json"
check "option range"        "config: sh_degree 9"           "$CFG/sh_degree_9.json"        splat-train "${T[@]}" --config "$CFG/sh_degree_9.json"
check "option conflict"     "config: batch 3, --iters 20"   "$CFG/batch_3.json|--iters"                        splat-train "${T[@]}" --config "$CFG/batch_3.json"
check "option conflict"     "config: official vs --strategy compact" "--strategy|$CFG/strategy_official.json"            splat-train "${T[@]}" --config "$CFG/strategy_official.json" --strategy compact
check "option conflict"     "config: near 20 > far 10"      "$CFG/near_beyond_far.json"             splat-train "${T[@]}" --config "$CFG/near_beyond_far.json"
check "option range"        "nerf config: depth 99"         "$CFG/nerf_depth_99.json"      splat-train "${T[@]}" --method nerf --config "$CFG/nerf_depth_99.json"
check "JSON of wrong shape" "nerf config: splat key"        "$CFG/sh_degree_9.json"        splat-train "${T[@]}" --method nerf --config "$CFG/sh_degree_9.json"
check "missing file"        "config: missing"               "$CFG/none.json"               splat-train "${T[@]}" --config "$CFG/none.json"

# --- splat-train: datasets (Blender, nerfstudio, COLMAP) ---
check "missing file"        "data: missing folder"          "$IN/nowhere"   splat-train "${TC[@]}" --data "$IN/nowhere"
check "wrong kind of file"  "data: empty folder"            "$BL/empty_folder" splat-train "${TC[@]}" --data "$BL/empty_folder"
check "missing file"        "blender: no transforms_test"   "$BL/no_test_json" splat-train "${TC[@]}" --data "$BL/no_test_json"
check "malformed JSON"      "blender: train JSON cut"       "$BL/train_malformed/transforms_train.json" splat-train "${TC[@]}" --data "$BL/train_malformed"
check "JSON of wrong shape" "blender: test frames {}"       "$BL/test_frames_object/transforms_test.json" splat-train "${TC[@]}" --data "$BL/test_frames_object"
check "bad value"           "blender: non-rigid matrix"     "$BL/train_nonrigid/transforms_train.json" splat-train "${TC[@]}" --data "$BL/train_nonrigid"
check "missing file"        "blender: image missing"        "views/view_1.png" splat-train "${TC[@]}" --data "$BL/image_missing"
check "truncated file"      "blender: PNG cut in half"      "views/view_1.png" splat-train "${TC[@]}" --data "$BL/image_cut"
check "mismatched sizes"    "blender: image 24px, camera 32" "views/view_1.png" splat-train "${TC[@]}" --data "$BL/image_24px"
check "huge count"          "blender: PNG header 60000^2"   "views/view_1.png" splat-train "${TC[@]}" --data "$BL/image_header_huge"
check "truncated file"      "blender: PNG cut before IEND"  "views/view_1.png" splat-train "${TC[@]}" --data "$BL/image_no_iend"
check "duplicate output names" "blender: two test views view_1" "$BL/test_duplicate_names/transforms_test.json" splat-train "${TC[@]}" --data "$BL/test_duplicate_names"
check "bad value"           "nerfstudio: OPENCV_FISHEYE"    "$NS/fisheye/transforms.json"         splat-train "${TC[@]}" --data "$NS/fisheye"
check "bad value"           "nerfstudio: k3 0.1"            "$NS/k3_nonzero/transforms.json"      splat-train "${TC[@]}" --data "$NS/k3_nonzero"
check "duplicate output names" "nerfstudio: view_0 twice"     "$NS/duplicate_names/transforms.json" splat-train "${TC[@]}" --data "$NS/duplicate_names"
check "missing file"        "nerfstudio: ply_file_path missing" "sparse_pc.ply" splat-train "${TC[@]}" --data "$NS/ply_missing"
check "wrong kind of file"  "nerfstudio: point cloud prose" "sparse_pc.ply"     splat-train "${TC[@]}" --data "$NS/ply_garbage"
check "huge count"          "nerfstudio: point cloud 9e8"   "sparse_pc.ply"     splat-train "${TC[@]}" --data "$NS/ply_count_huge"
check "missing file"        "nerfstudio: mask missing"      "masks/view_1.png"  splat-train "${TC[@]}" --data "$NS/mask_missing"
check "mismatched sizes"    "nerfstudio: mask 8px"          "masks/view_1.png"  splat-train "${TC[@]}" --data "$NS/mask_8px"
check "bad value"           "colmap txt: OPENCV_FISHEYE"    "cameras.txt"  splat-train "${TC[@]}" --data "$COL/text_model_fisheye"
check "bad value"           "colmap txt: 3 PINHOLE params"  "cameras.txt"  splat-train "${TC[@]}" --data "$COL/text_params_short"
check "NaN/Inf"             "colmap txt: fx nan"            "cameras.txt"  splat-train "${TC[@]}" --data "$COL/text_camera_nan"
check "bad value"           "colmap txt: k1 100 (covers <1/2)" "cameras.txt" splat-train "${TC[@]}" --data "$COL/text_distortion_extreme"
check "bad value"           "colmap txt: unknown camera 7"  "images.txt"   splat-train "${TC[@]}" --data "$COL/text_unknown_camera"
check "bad value"           "colmap txt: zero quaternion"   "images.txt"   splat-train "${TC[@]}" --data "$COL/text_zero_quaternion"
check "duplicate output names" "colmap txt: duplicate name" "images.txt"   splat-train "${TC[@]}" --data "$COL/text_duplicate_name"
check "bad value"           "colmap txt: word in number"    "images.txt"   splat-train "${TC[@]}" --data "$COL/text_word_in_number"
check "truncated file"      "colmap txt: short image line"  "images.txt"   splat-train "${TC[@]}" --data "$COL/text_short_image_line"
check "empty file"          "colmap txt: no points"         "points3D.txt" splat-train "${TC[@]}" --data "$COL/text_no_points"
check "missing file"        "colmap txt: no images.txt"     "images"       splat-train "${TC[@]}" --data "$COL/text_no_images_txt"
check "missing file"        "colmap txt: photo missing"     "nope.png"     splat-train "${TC[@]}" --data "$COL/text_photo_missing"
check "trailing bytes"      "colmap bin: cameras.bin junk"  "cameras.bin"  splat-train "${TC[@]}" --data "$COL/binary_cameras_trailing"
check "truncated file"      "colmap bin: images.bin cut"    "images.bin"   splat-train "${TC[@]}" --data "$COL/binary_images_cut"
check "huge count"          "colmap bin: 2^60 points"       "points3D.bin" splat-train "${TC[@]}" --data "$COL/binary_points_count_huge"
check "truncated file"      "colmap bin: name unterminated" "images.bin"   splat-train "${TC[@]}" --data "$COL/binary_name_unterminated"
check "empty file"          "colmap bin: no cameras"        "cameras.bin"  splat-train "${TC[@]}" --data "$COL/binary_no_cameras"
check "huge count"          "colmap bin: width 2^40"        "cameras.bin"  splat-train "${TC[@]}" --data "$COL/binary_width_huge"
check "option range"        "colmap: --holdout-every 1 (no train)" "--holdout-every|images.txt" splat-train "${TC[@]}" --data "$COL/text_valid" --holdout-every 1

# --- splat-train --resume ---
check "missing file"        "resume: missing"               "$CKD/none.ckpt"          splat-train "${TC[@]}" --resume "$CKD/none.ckpt"
check "missing file"        "resume: folder without .ckpt"  "$CKD/folder_without_checkpoint" splat-train "${TC[@]}" --resume "$CKD/folder_without_checkpoint"
check "wrong magic"         "resume: magic"                 "$CKD/bad_magic.ckpt"     splat-train "${TC[@]}" --resume "$CKD/bad_magic.ckpt"
check "bad header"          "resume: version 9"             "$CKD/version_9.ckpt"     splat-train "${TC[@]}" --resume "$CKD/version_9.ckpt"
check "huge count"          "resume: header length 2^62"    "$CKD/header_length_huge.ckpt" splat-train "${TC[@]}" --resume "$CKD/header_length_huge.ckpt"
check "truncated file"      "resume: cut in header"         "$CKD/cut_in_header.ckpt" splat-train "${TC[@]}" --resume "$CKD/cut_in_header.ckpt"
check "truncated file"      "resume: cut last byte"         "$CKD/cut_last_byte.ckpt" splat-train "${TC[@]}" --resume "$CKD/cut_last_byte.ckpt"
check "truncated file"      "resume: cut in arrays"         "$CKD/cut_in_arrays.ckpt" splat-train "${TC[@]}" --resume "$CKD/cut_in_arrays.ckpt"
check "trailing bytes"      "resume: junk at the end"       "$CKD/trailing.ckpt"      splat-train "${TC[@]}" --resume "$CKD/trailing.ckpt"
check "NaN/Inf"             "resume: NaN mean"              "$CKD/nan_mean.ckpt"      splat-train "${TC[@]}" --resume "$CKD/nan_mean.ckpt"
check "NaN/Inf"             "resume: Inf Adam moment"       "$CKD/inf_adam_moment.ckpt" splat-train "${TC[@]}" --resume "$CKD/inf_adam_moment.ckpt"
check "huge count"          "resume: array count 2^60"      "$CKD/count_huge.ckpt"    splat-train "${TC[@]}" --resume "$CKD/count_huge.ckpt"
check "malformed JSON"      "resume: header JSON cut"       "$CKD/header_malformed.ckpt" splat-train "${TC[@]}" --resume "$CKD/header_malformed.ckpt"
check "bad value"           "resume: iteration -1"          "$CKD/iteration_negative.ckpt" splat-train "${TC[@]}" --resume "$CKD/iteration_negative.ckpt"
check "bad value"           "resume: rng garbage"           "$CKD/rng_garbage.ckpt"   splat-train "${TC[@]}" --resume "$CKD/rng_garbage.ckpt"
check "malformed JSON"      "resume: folder, metrics.json cut" "$CKD/resume_metrics_malformed/metrics.json" splat-train "${TC[@]}" --resume "$CKD/resume_metrics_malformed"
check "JSON of wrong shape" "resume: folder, history 7"     "$CKD/resume_metrics_shape/metrics.json" splat-train "${TC[@]}" --resume "$CKD/resume_metrics_shape"
check "resume"              "resume: other dataset (same count)" "$CK"                splat-train "${TC[@]}" --data "$IN/ds_other" --resume "$CK"
check "resume"              "resume: other dataset (3 views)" "$CK"                   splat-train "${TC[@]}" --data "$BL/three_views" --resume "$CK"
check "resume"              "resume: NeRF checkpoint, splat run" "$NCK"               splat-train "${TC[@]}" --resume "$NCK"
check "resume"              "resume: splat checkpoint, NeRF run" "$CK"                splat-train "${TN[@]}" --resume "$CK"
# The checkpoint carries its networks (version 3): a config with other ones is refused.
check "resume"              "resume: NeRF, other network shape" "--config"            splat-train --data "$DS" --out "$NEW" --iters 20 --threads 1 --quiet --method nerf --config "$IN/other_nerf.json" --resume "$NCK"
check "resume"              "resume: --strategy official on compact" "--strategy"     splat-train "${TC[@]}" --strategy official --resume "$CK"
check "resume"              "resume: --iters below checkpoint" "--iters"              splat-train "${TC[@]}" --iters 5 --resume "$CK"
check "huge count"          "resume nerf: RNG length 2^40"  "$NCKD/rng_length_huge.ckpt" splat-train "${TN[@]}" --resume "$NCKD/rng_length_huge.ckpt"
check "truncated file"      "resume nerf: cut half"         "$NCKD/cut_half.ckpt"     splat-train "${TN[@]}" --resume "$NCKD/cut_half.ckpt"
check "trailing bytes"      "resume nerf: junk at the end"  "$NCKD/trailing.ckpt"     splat-train "${TN[@]}" --resume "$NCKD/trailing.ckpt"
unreadable "unreadable file" "resume: chmod 000" "$CK" "$CK" splat-train "${TC[@]}" --resume "$CK"

# --- splat-eval ---
check "option range"        "eval --max-seconds 0"          "--max-seconds" splat-eval "${E[@]}" --max-seconds 0
check "option range"        "eval --eval-every-seconds -1"  "--eval-every-seconds" splat-eval "${E[@]}" --eval-every-seconds -1
check "option range"        "eval --threads 0"              "--threads"  splat-eval "${E[@]}" --threads 0
check "option range"        "eval --downscale 0"            "--downscale" splat-eval "${E[@]}" --downscale 0
check "option range"        "eval --bg 5,5,5"               "--bg"       splat-eval "${E[@]}" --bg 5,5,5
check "option range"        "eval --fly-through 0"          "--fly-through" splat-eval "${E[@]}" --fly-through 0
check "option range"        "eval --methods gauss"          "--methods"  splat-eval "${E[@]}" --methods splat,gauss
check "option range"        "eval --sweep-gaussians 0"      "--sweep-gaussians" splat-eval "${E[@]}" --sweep-gaussians 0
check "option range"        "eval --stability-views 0"      "--stability-views" splat-eval "${E[@]}" --stability --stability-views 0
check "option range"        "eval --pose-noise -1"          "--pose-noise" splat-eval "${E[@]}" --stability --pose-noise -1
check "malformed JSON"      "eval --splat-config cut"       "$CFG/malformed.json"   splat-eval "${E[@]}" --splat-config "$CFG/malformed.json"
check "JSON of wrong shape" "eval --nerf-config splat key"  "$CFG/sh_degree_9.json" splat-eval "${E[@]}" --methods nerf --nerf-config "$CFG/sh_degree_9.json"
check "missing file"        "eval --data missing"           "$IN/nowhere"      splat-eval "${E[@]}" --data "$IN/nowhere"
check "malformed JSON"      "eval: Blender train JSON cut"  "$BL/train_malformed/transforms_train.json" splat-eval "${E[@]}" --data "$BL/train_malformed"
check "wrong kind of file"  "eval --out is a file"          "$IN/a_file"       splat-eval "${E[@]}" --out "$IN/a_file"
check "unknown option"      "eval --budget"                 "--budget"   splat-eval "${E[@]}" --budget 5
check "missing required option" "eval without --data"       "--data"     splat-eval --out "$NEW" --max-seconds 1
# Empty histories beside final scores still chart the finals (PSNR against size): a report.
control "eval --report: empty histories, final scores" splat-eval --report --quiet --out "$REP/empty_histories"
check "empty report"        "eval --report: nothing scored" "$REP/nothing_scored/results.json" splat-eval --report --quiet --out "$REP/nothing_scored"
check "empty report"        "eval --report: no result files" "$REP/no_result_files" splat-eval --report --quiet --out "$REP/no_result_files"
check "malformed JSON"      "eval --report: results cut"    "$REP/results_malformed/results.json"  splat-eval --report --quiet --out "$REP/results_malformed"
check "JSON of wrong shape" "eval --report: psnr \"high\""  "$REP/results_wrong_type/results.json" splat-eval --report --quiet --out "$REP/results_wrong_type"
check "JSON of wrong shape" "eval --report: sweep runs 5"   "$REP/sweep_wrong_shape/sweep.json"    splat-eval --report --quiet --out "$REP/sweep_wrong_shape"
check "nothing created on failure" "eval --report: no \"data\" key" "$REP/results_without_data/results.json" splat-eval --report --quiet --out "$REP/results_without_data"
check "wrong kind of file"  "eval --report: results.json folder" "$REP/results_folder/results.json" splat-eval --report --quiet --out "$REP/results_folder"
check "missing file"        "eval --report: no such folder" "$IN/nowhere"      splat-eval --report --quiet --out "$IN/nowhere"
check "option conflict"     "eval --report with --data"     "--data"     splat-eval --report --quiet --out "$IN/ev" --data "$DS"

# ---------------------------------------------------------------------------------------------
# Summary
# ---------------------------------------------------------------------------------------------
echo
echo "Per class:"
printf '  %-28s %5s %5s %5s\n' CLASS CASES OK FAIL
for class in "${CLASS_ORDER[@]}"; do
  printf '  %-28s %5d %5d %5d\n' "$class" "${CLASS_TOTAL[$class]}" \
    $((CLASS_TOTAL[$class] - CLASS_FAIL[$class])) "${CLASS_FAIL[$class]}"
done
echo
echo "Total: $N_CASES cases, $((N_CASES - N_FAIL)) OK, $N_FAIL FAIL, $N_SKIP skipped; controls failed: $N_CONTROL_FAIL"
((N_RERUN)) && echo "($N_RERUN runs repeated because a binary was missing or being rebuilt at the time)"
if ((N_SKIP)); then
  echo "Skipped:"; printf '  %s\n' "${SKIPS[@]}"
fi
if ((N_FAIL)); then
  echo
  echo "FAIL details (\$S = the scratch folder; KEEP=1 keeps it):"
  printf '%s\n\n' "${FAIL_RECORDS[@]}"
fi
if ((N_FAIL == 0 && N_CONTROL_FAIL == 0)); then exit 0; else exit 1; fi
