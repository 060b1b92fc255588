0 0 0 0 0 1
# a comment
1 1 1 0 1
