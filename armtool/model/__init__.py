"""Loading robot descriptions: package paths, xacro expansion with source lines."""
