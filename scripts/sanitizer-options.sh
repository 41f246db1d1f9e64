# Sourced by scripts/test.sh --sanitize and bench/fuzz.sh: how the sanitized programs report.
# UBSan stops at the first report (the build also uses -fno-sanitize-recover=undefined) with a
# stack; LeakSanitizer skips the libraries listed in scripts/lsan.supp.
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/lsan.supp:print_suppressions=0"
