# Shared by the scripts that run a document's example as printed (sourced, not run): the example
# is the first ```sh block after a heading, one `build/mblab serve ... &` line that serves and one
# line that tests it, run from the repository root. Cleans up the served device by PID on exit.

# run_doc_example FILE HEADING COMMAND OUT [READY]: serves as printed, waits until the device
# prints READY (by default the port its line names), runs the `build/mblab COMMAND` line with its
# output in OUT, and returns its exit status. Skips (exit 0) when build/mblab is not built.
run_doc_example() {
    doc_root="$(cd "$(dirname "$0")/../.." && pwd)"
    cd "$doc_root" || exit 1
    [ -x build/mblab ] || { echo "SKIP: build/mblab is not built here"; exit 0; }
    block=$(awk -v heading="$2" 'index($0, heading) == 1 {on=1} on&&/^```sh/{grab=1;next} grab&&/^```/{exit} grab{print}' "$1")
    serve=$(printf '%s\n' "$block" | grep '^build/mblab serve ')
    example=$(printf '%s\n' "$block" | grep "^build/mblab $3 ")
    [ -n "$serve" ] && [ -n "$example" ] || { echo "FAIL: the example in $1 is not found"; exit 1; }
    serve=${serve% &}
    ready=${5:-$(printf '%s\n' "$serve" | sed -n 's/.*tcp:\/\/127\.0\.0\.1:\([0-9]*\).*/\1/p')}
    doc_work=$(mktemp -d)
    trap 'kill "$doc_serve_pid" 2>/dev/null; wait 2>/dev/null; rm -rf "$doc_work"' EXIT
    sh -c "exec $serve" >"$doc_work/serve.out" 2>"$doc_work/serve.err" &
    doc_serve_pid=$!
    for _ in $(seq 100); do
        grep -q "$ready" "$doc_work/serve.out" 2>/dev/null && break
        sleep 0.1
    done
    sh -c "$example" >"$4" 2>&1
    status=$?
    cat "$4"
    [ "$status" = 0 ] || cat "$doc_work/serve.err"
    return "$status"
}
