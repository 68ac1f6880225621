# bash completion for fdmsurf and msms (fdmsurf with MSMS's command line): subcommands, options,
# option values (surfaces, methods, colour schemes, views, formats, ...) and file names, the
# structure files by their extensions. Installed as share/bash-completion/completions/fdmsurf
# (and msms, a link to it), where bash-completion finds it; elsewhere: source this file.
# tests/packaging/test_completion.py checks the options and values against the program's own
# --help and messages, so that the two cannot drift apart.

_fdmsurf_options='--surface --method --spacing --probe --cutoff --sigma --level --filter --paper
    --no-cavities --min-cavity-volume --padding --refine --no-snap --chord-tolerance
    --natural-grid --format --model --models --assembly --waters --hydrogens --no-ligands
    --chains --select --patch --color --properties --simplify --max-triangles --simplifier
    --optimize --device --list-devices --validation --host-filter --host-density --host-mc
    --host-atoms --host-ses -o --output --output-format --stats --quiet -h --help --version --areas
    --relative --buried --image --image-size --view --views --rotate --background --outline
    --occlusion --depth-cue'
_fdmsurf_compare_options='--spacing --stats --outer --weld-tol -h --help'
_fdmsurf_prepare_options='--device --validation --quiet -h --help'
_fdmsurf_msms_options='-if -of -af -probe_radius -density -hdensity -no_area -surface
    -all_components -no_header -spacing -method -device -validation -host_filter -host_density
    -host_mc -host_atoms -host_ses -h -help'
_fdmsurf_structures='pdb|ent|cif|mmcif|pqr|xyzr|xyzrn'
_fdmsurf_meshes='ply|obj|glb|stl|off|vert|face'

# The values an option takes, space-separated; "" when it takes none that can be listed (a
# number, a selection); "FILES" or "FILES:regex" for a file name.
_fdmsurf_values() {
    case $1 in
        --surface) echo 'ses vdw sas' ;;
        --method) echo 'fdm edt' ;;
        --filter) echo 'ideal gaussian' ;;
        --format) echo 'pdb cif pqr xyzr xyzrn' ;;
        --models) echo 'all' ;;
        --color) echo 'chain element residue hydrophobicity bfactor coulombic none' ;;
        --properties) echo 'coulombic hydrophobicity bfactor mean_curvature gaussian_curvature shape_index' ;;
        --simplifier) echo 'collapse meshopt' ;;
        --host-filter | --host-density | --host-mc | --host-atoms | --host-ses) echo 'auto on off' ;;
        --output-format) echo 'ply obj glb stl off png' ;;
        --stats) echo 'json text' ;;
        --relative) echo 'tien2013 miller1987 sander1994' ;;
        --view | --views) echo 'front back left right top bottom' ;;
        --background) echo 'white black transparent' ;;
        -o | --output) echo 'FILES' ;;
        --areas) echo 'FILES:csv|json' ;;
        --image) echo 'FILES:png' ;;
        --device | -device) echo 'DEVICES' ;;
        # msms
        -if) echo 'FILES:xyzr|xyzrn' ;;
        -of | -af) echo 'FILES' ;;
        -surface) echo 'tses ses ases' ;;
        -method) echo 'edt fdm' ;;
        -host_filter | -host_density | -host_mc | -host_atoms | -host_ses) echo 'auto on off' ;;
        # compare
        compare:--stats) echo 'json' ;;
        *) return 1 ;;  # an option that takes no value, or not an option
    esac
}

# Options that take a value (the next word), for each command.
_fdmsurf_takes_value() {
    case $1 in
        --surface | --method | --spacing | --probe | --cutoff | --sigma | --level | --filter | \
        --min-cavity-volume | --padding | --refine | --chord-tolerance | --format | --model | \
        --models | --assembly | --chains | --select | --patch | --color | --properties | \
        --simplify | --max-triangles | --simplifier | --device | --host-filter | --host-density | \
        --host-mc | --host-atoms | --host-ses | -o | --output | --output-format | --stats | \
        --areas | --relative | --buried | --image | --image-size | --view | --views | --rotate | \
        --background | --occlusion | --depth-cue | --weld-tol | -if | -of | -af | \
        -probe_radius | -density | -hdensity | -surface | -spacing | -method | -device | \
        -host_filter | -host_density | -host_mc | -host_atoms | -host_ses) return 0 ;;
    esac
    return 1
}

# File names under $1 (the word so far), those matching the extensions $2 (a regex alternative,
# gzipped or not; empty: every file), and folders.
_fdmsurf_files() {
    local name
    compopt -o filenames 2>/dev/null
    while IFS= read -r name; do
        if [[ -d $name || -z $2 ]] || [[ $name =~ \.($2)(\.gz)?$ ]]; then
            COMPREPLY+=("$name")
        fi
    done < <(compgen -f -- "$1")
}

_fdmsurf() {
    local cur=${COMP_WORDS[COMP_CWORD]} prev=
    ((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
    # --name=value: bash splits it at '=' (COMP_WORDBREAKS) into --name, = and the value.
    if [[ $cur == = ]]; then
        ((COMP_CWORD > 1)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
        cur=
    elif [[ $prev == = ]] && ((COMP_CWORD > 1)); then
        prev=${COMP_WORDS[COMP_CWORD - 2]}
    fi
    COMPREPLY=()

    local command=${COMP_WORDS[0]##*/} options=$_fdmsurf_options
    if [[ $command == msms ]]; then
        command=msms
    elif [[ ${COMP_WORDS[1]:-} =~ ^(compare|msms|prepare)$ ]] && ((COMP_CWORD > 1)); then
        command=${COMP_WORDS[1]}
    else
        command=fdmsurf
    fi
    case $command in
        compare) options=$_fdmsurf_compare_options ;;
        prepare) options=$_fdmsurf_prepare_options ;;
        msms) options=$_fdmsurf_msms_options ;;
    esac

    local values
    if _fdmsurf_takes_value "$prev"; then
        values=$(_fdmsurf_values "$command:$prev" || _fdmsurf_values "$prev") || return 0
        case $values in
            FILES) _fdmsurf_files "$cur" '' ;;
            FILES:*) _fdmsurf_files "$cur" "${values#FILES:}" ;;
            DEVICES)
                local fdmsurf=${COMP_WORDS[0]}  # msms: the fdmsurf beside it, or on PATH
                [[ ${fdmsurf##*/} == msms ]] && fdmsurf=${fdmsurf%msms}fdmsurf
                values=$("$fdmsurf" --list-devices 2>/dev/null | sed -n 's/^device \([0-9]*\):.*/\1/p')
                COMPREPLY=($(compgen -W "$values" -- "$cur"))
                ;;
            *)
                # Comma-separated lists (--properties, --view): complete the last item.
                local head=
                if [[ ($prev == --properties || $prev == --view || $prev == --views) && $cur == *,* ]]; then
                    head=${cur%,*},
                fi
                local word
                for word in $(compgen -W "$values" -- "${cur##*,}"); do
                    COMPREPLY+=("$head$word")
                done
                ;;
        esac
        return 0
    fi

    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$options" -- "$cur"))
        return 0
    fi
    case $command in
        fdmsurf)
            ((COMP_CWORD == 1)) && COMPREPLY=($(compgen -W 'compare msms prepare' -- "$cur"))
            _fdmsurf_files "$cur" "$_fdmsurf_structures"
            ;;
        compare) _fdmsurf_files "$cur" "$_fdmsurf_meshes" ;;
    esac
    return 0
}

complete -F _fdmsurf fdmsurf msms
