"""The paper's experiment and the records experiments write: the paper's figures and way points, the
offline experiment, Table 2 as a typed record (its JSON and its Markdown), Table 2 measured from a
recording, each move's energy row, a refit written to its folder."""
