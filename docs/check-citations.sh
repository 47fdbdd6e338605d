#!/bin/sh
# Every "methods.md §x[.y]" / "scenes.md §x[.y]" cited in the repository must be a heading
# of docs/methods.md / docs/scenes.md ("## x." or "### x.y ").
cd "$(git rev-parse --show-toplevel)" || exit 2
status=0
for doc in methods scenes; do
  cited=$(grep -rhoE "${doc}\.md §[0-9]+(\.[0-9]+)*" crates xtask benches docs models README.md \
          | sed -E 's/.*§//' | sort -uV)
  n=0; bad=0
  for s in $cited; do
    n=$((n + 1))
    case "$s" in
      *.*) pat="^### $(echo "$s" | sed 's/\./\\./g') " ;;
      *)   pat="^## $s\. " ;;
    esac
    if ! grep -qE "$pat" "docs/$doc.md"; then
      echo "MISSING: $doc.md §$s"; bad=$((bad + 1)); status=1
    fi
  done
  echo "docs/$doc.md: $n distinct sections cited, $bad missing ($(echo $cited | tr '\n' ' '))"
done
exit $status
