# bash completion for mblab(1); installed as share/bash-completion/completions/mblab.
# Options are read from `mblab COMMAND --help` of the binary being completed, so the completion
# never lists an option that binary lacks or misses one it gained.

_mblab_options() {
    "$@" --help 2>/dev/null | sed -nE 's/^ +((-[A-Za-z]),)?(--[A-Za-z][-A-Za-z0-9]*).*/\2 \3/p'
}

# The shipped profiles the binary knows (built in, or installed beside it), as its refusal of an
# unknown one names them.
_mblab_profiles() {
    "$1" serve ./mblab-completion-asks-for-profile-names 2>&1 |
        sed -nE 's/.*\(shipped: (.*)\)$/\1/p' | tr -d ','
}

_mblab() {
    local cur prev words cword
    if declare -F _init_completion >/dev/null; then
        _init_completion || return
    else
        cur="${COMP_WORDS[COMP_CWORD]}"
        prev="${COMP_WORDS[COMP_CWORD - 1]}"
        words=("${COMP_WORDS[@]}")
        cword=$COMP_CWORD
    fi
    local commands="conform conform-client serve read write diag devid raw watch sunspec load pki fuzz scan profile"
    local command="" i
    for ((i = 1; i < cword; i++)); do
        case " $commands " in *" ${words[i]} "*) command="${words[i]}"; break ;; esac
    done
    if [[ -z $command ]]; then
        COMPREPLY=($(compgen -W "$commands --help --version -h -V" -- "$cur"))
        return
    fi
    case $prev in
        --suite)
            COMPREPLY=($("${words[0]}" conform --list 2>/dev/null | sed -nE 's/^([^ ]+) \(.*/\1/p'))
            COMPREPLY=($(compgen -W "${COMPREPLY[*]}" -- "$cur") $(compgen -f -- "$cur"))
            return
            ;;
        --json)
            # conform, conform-client, load and fuzz write a report there; for the client commands
            # it is a flag.
            if [[ $command == conform* || $command == load || $command == fuzz ]]; then
                COMPREPLY=($(compgen -f -- "$cur"))
                return
            fi
            ;;
        --profile)
            COMPREPLY=($(compgen -W "$(_mblab_profiles "${words[0]}")" -- "$cur") $(compgen -f -- "$cur"))
            return
            ;;
        --dut | --declare | --junit | --pcap | --html | --state | --devices | --cert | --key | --ca | \
            --replay | --reproducer | --learn | --http-token-file | --output | -o)
            COMPREPLY=($(compgen -f -- "$cur"))
            return
            ;;
        --catalogue | --pki | --report-dir | --sunspec-models)
            COMPREPLY=($(compgen -d -- "$cur"))
            return
            ;;
        --key-type)
            COMPREPLY=($(compgen -W "ec rsa" -- "$cur"))
            return
            ;;
        --class | --skip-class)
            # A comma-separated list: the class after the last comma is completed.
            local classes="protocol-id mbap-length oversize truncated quantity byte-count address-wrap
                unknown-function sub-function file-record unit-id split-frame partial-header pipelined
                many-connections slow-reader half-open flood boundary frame-check short-frame line-gap
                noise ascii-text pairwise mutation"
            local head="" last="$cur"
            if [[ $cur == *,* ]]; then head="${cur%,*},"; last="${cur##*,}"; fi
            COMPREPLY=($(compgen -P "$head" -W "$classes" -- "$last"))
            return
            ;;
        --base)
            COMPREPLY=($(compgen -W "0 1" -- "$cur"))
            return
            ;;
        --format)
            COMPREPLY=($(compgen -W "text ndjson csv" -- "$cur"))
            return
            ;;
        --role | --server-name | --days | --read-only-role | --write-role | --restart | --writable | \
            --http | --http-token | --http-allow-host | --metrics | --device-pid | --units | \
            --client-unit | --client-timeout | --client-retries | --error-pattern | --value-pattern | \
            --monitor | --baseline | --degraded-limit | --ladder | --ladder-step)
            return
            ;;
    esac
    # profile is a group: its subcommand comes first, and has the options.
    if [[ $command == profile ]]; then
        if ((cword == i + 1)); then
            COMPREPLY=($(compgen -W "import-csv" -- "$cur"))
            return
        fi
        if [[ $cur == -* ]]; then
            COMPREPLY=($(compgen -W "$(_mblab_options "${words[0]}" profile "${words[i + 1]}")" -- "$cur"))
            return
        fi
        [[ $prev == --unit || $prev == --name ]] && return
        COMPREPLY=($(compgen -f -X '!*.csv' -- "$cur") $(compgen -d -- "$cur"))
        return
    fi
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$(_mblab_options "${words[0]}" "$command")" -- "$cur"))
        return
    fi
    # serve's one argument is the profile.
    if [[ $command == serve ]]; then
        COMPREPLY=($(compgen -W "$(_mblab_profiles "${words[0]}")" -- "$cur") $(compgen -f -- "$cur"))
        return
    fi
    # pki's one argument is the directory it writes into.
    if [[ $command == pki ]]; then
        COMPREPLY=($(compgen -d -- "$cur"))
        return
    fi
    COMPREPLY=($(compgen -f -- "$cur"))
}

complete -F _mblab mblab
