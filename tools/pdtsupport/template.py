"""A report's template file in parts (docs/reports/): each part begins with
a line "@@ name" and is a string.Template."""
import pathlib
import re
import string


def parts(path):
    """{name: string.Template} of the template file at path. A part's text
    runs to the next "@@ name" line, less the newline that ends its last
    line: a part that ends in an empty line ends in a newline."""
    chunks = re.split(r"^@@ (\w+)\n", pathlib.Path(path).read_text(), flags=re.M)
    return {name: string.Template(text[:-1] if text.endswith("\n") else text)
            for name, text in zip(chunks[1::2], chunks[2::2])}
