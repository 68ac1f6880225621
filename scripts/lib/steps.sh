# fail and step for the install scripts (scripts/pip-test.sh, scripts/package-test.sh), sourced
# after they set `script` (their name, for messages) and `work` (the folder for step logs).

fail() {
    echo "$script: $*" >&2
    exit 1
}

step() {  # step NAME COMMAND...: COMMAND's output in a log, shown when it fails
    local name=$1 start=$SECONDS
    shift
    if ! "$@" >"$work/$name.log" 2>&1; then
        cat "$work/$name.log" >&2
        fail "$name failed (its output is above)"
    fi
    echo "$script: $name ($((SECONDS - start)) s)"
}
