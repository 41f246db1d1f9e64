# Shared by the benchmark scripts (source it after setting $train and $out):
#   run NAME ARGS...   one splat-train into OUT/NAME, its output kept in OUT/NAME.log
run() {
  local name=$1
  shift
  echo "$(date +%T) $name: splat-train $*"
  "$train" --out "$out/$name" --checkpoint-every 0 --quiet "$@" > "$out/$name.log" 2>&1 ||
    echo "  failed: see $out/$name.log"
}
