"""Print the shell commands of README.md's "## The two commands" section, one per line."""
import re
import sys

text = open(sys.argv[1], encoding="utf-8").read()
section = re.search(r"^## The two commands\n(.*?)(?=^## )", text, re.S | re.M)
for block in re.findall(r"```sh\n(.*?)```", section.group(1) if section else "", re.S):
    print(" ".join(line.strip() for line in block.strip().splitlines()))
