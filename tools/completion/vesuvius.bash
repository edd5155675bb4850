# bash completion for the Vesuvius tools (installed as
# share/bash-completion/completions/vsv-* ). Options come from each tool's
# own --help, so they never go stale; values for the options that take a
# fixed set; file names otherwise.
_vsv_complete()
{
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]} tool=${COMP_WORDS[0]}
    case $prev in
    -r|--renderer) COMPREPLY=($(compgen -W "raycast shearwarp" -- "$cur")); return ;;
    --loop) COMPREPLY=($(compgen -W "on off bounce" -- "$cur")); return ;;
    --vertical) COMPREPLY=($(compgen -W "even native" -- "$cur")); return ;;
    --scale) COMPREPLY=($(compgen -W "linear log" -- "$cur")); return ;;
    --codec) COMPREPLY=($(compgen -W "zstd none" -- "$cur")); return ;;
    --bits) COMPREPLY=($(compgen -W "8 16" -- "$cur")); return ;;
    --colormap) [[ ${tool##*/} == vsv-plot ]] &&
        { COMPREPLY=($(compgen -W "viridis magma cividis inferno plasma clouds rain ice snow graupel greys" -- "$cur")); return; } ;;
    -s|--species|--vars)
        # species of the first .vsv named on the line
        local w f
        for w in "${COMP_WORDS[@]:1}"; do
            [[ $w == *.vsv && -f $w ]] && { f=$w; break; }
        done
        if [[ -n $f ]]; then
            local names="" i=0 n
            while n=$(vsv-info -f "species.$i.name" "$f" 2>/dev/null) && [[ -n $n ]]; do
                names+="$n "
                i=$((i + 1))
            done
            local pre=""
            [[ $cur == *,* ]] && pre=${cur%,*},
            COMPREPLY=($(compgen -P "$pre" -W "$names" -- "${cur##*,}"))
            return
        fi ;;
    esac
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$("$tool" --help 2>/dev/null | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)" -- "$cur"))
    else
        compopt -o filenames 2>/dev/null
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
}
complete -F _vsv_complete vsv-pack vsv-info vsv-extract vsv-interp vsv-convert vsv-convert-mpi vsv-render vsv-play vsv-export vsv-query vsv-plot
