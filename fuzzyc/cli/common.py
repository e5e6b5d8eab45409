"""What the command modules share."""

# What every command that reads through formats.load_any says of its rule-file argument.
RULE_FILE_HELP = ("a .fz, .fll, .fcl or .fis rule file; FILE.fcl::NAME reads the FUNCTION_BLOCK "
                  "NAME of an FCL file that has several")
