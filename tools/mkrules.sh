#!/bin/sh
# Make rules for Fortran objects: one explicit compile rule per source and
# build directory, plus the module dependencies found from `module`/`use`.
# usage: mkrules.sh "DIR:FLAGVAR DIR:FLAGVAR ..." file...
configs=$1; shift
awk -v configs="$configs" '
function flat(f) { sub(/^src\//, "", f); sub(/^tests\//, "tests_", f); gsub(/\//, "_", f); sub(/\.[fF]90$/, ".o", f); return f }
FNR == 1 { files[++nf] = FILENAME }
{ line = tolower($0) }
line ~ /^[ \t]*module[ \t]+[a-z0-9_]+[ \t]*(!.*)?$/ {
    n = line; sub(/^[ \t]*module[ \t]+/, "", n); sub(/[ \t!].*$/, "", n); provider[n] = FILENAME }
line ~ /^[ \t]*use[ \t,]/ {
    s = line; sub(/^[ \t]*use[ \t]*(,[ \t]*(non_)?intrinsic[ \t]*::)?[ \t]*/, "", s); sub(/[ \t,!].*$/, "", s)
    uses[FILENAME] = uses[FILENAME] " " s }
END {
    nc = split(configs, cfg, " ")
    for (c = 1; c <= nc; c++) {
        split(cfg[c], parts, ":"); dir = parts[1]; flags = parts[2]
        for (i = 1; i <= nf; i++) {
            f = files[i]; o = dir "/" flat(f)
            deps = ""
            m = split(uses[f], u, " ")
            for (j = 1; j <= m; j++) if ((u[j] in provider) && provider[u[j]] != f) deps = deps " " dir "/" flat(provider[u[j]])
            print o ": " f deps
            print "\t@mkdir -p " dir
            print "\t$(FC) $(" flags ") -J" dir " -I" dir " -c " f " -o " o
        }
    }
}' "$@"
