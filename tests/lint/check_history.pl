#!/usr/bin/perl
# History belongs in git, not in the manual or the code: fails when README.md, a markdown file
# or a code comment holds an ISO date (YYYY-MM-DD), a commit hash (a word of 7-40 hex digits
# with at least one letter and one digit) or an issue reference (the word issue and a number).
#   check_history.pl ROOT [ALLOW_FILE]
# Markdown files are checked whole; C++, GLSL and CMake/shell/Python/TOML files only in their
# comments (after // or #, and inside /* */), so that checksums and numbers in code and test data
# stay out of it. ALLOW_FILE lists lines that must name a version (a dataset's fetch, a program's
# source commit) as "PATH: TEXT": a hit on a line of PATH that contains TEXT is allowed.
use strict;
use warnings;
use File::Find;

my ($root, $allowFile) = @ARGV;
die "usage: check_history.pl ROOT [ALLOW_FILE]\n" unless defined $root && -d $root;

my @allow;
if (defined $allowFile) {
  open(my $a, '<', $allowFile) or die "cannot read $allowFile: $!\n";
  while (<$a>) {
    chomp;
    next if /^\s*(#|$)/;
    my ($path, $text) = /^([^:]+):\s?(.*)$/ or die "$allowFile:$.: not 'PATH: TEXT': $_\n";
    push @allow, [$path, $text];
  }
}

my $date = qr/\b(?:19|20)\d\d-(?:0[1-9]|1[0-2])-(?:0[1-9]|[12]\d|3[01])\b/;
my $hash = qr/\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b/;
my $issue = qr/\b[Ii]ssues?\s+#?\d+/;

my @files;
find(
  {
    no_chdir => 1,
    preprocess => sub {
      return grep { !($File::Find::dir eq $root && /^(?:build.*|out|\.git)$/) } @_;
    },
    wanted => sub { push @files, $File::Find::name if -f $_ },
  },
  $root);

my $problems = 0;
for my $file (sort @files) {
  (my $rel = $file) =~ s/^\Q$root\E\/?//;
  next if $rel =~ m{^tests/(?:data|fuzz/seeds)/} || $rel =~ m{^tests/golden/.*/checksum\.txt$};
  my $kind;
  if ($rel =~ /\.md$/) { $kind = 'all' }
  elsif ($rel =~ /\.(?:cpp|h|glsl|vert|frag|comp)$/) { $kind = 'slash' }
  elsif ($rel =~ /(?:CMakeLists\.txt|\.cmake|\.sh|\.py|\.toml|\.supp|\.pl)$/ || $rel =~ m{^\.ci/}) {
    $kind = 'hash';
  }
  next unless $kind;
  open(my $in, '<', $file) or die "cannot read $file: $!\n";
  my $inBlock = 0;
  while (my $line = <$in>) {
    my $text = '';
    if ($kind eq 'all') {
      $text = $line;
    } elsif ($kind eq 'hash') {
      $text = $1 if $line =~ /(#.*)$/;
    } else {
      my $rest = $line;
      while (length $rest) {
        if ($inBlock) {
          if ($rest =~ s/^(.*?)\*\///) { $text .= $1; $inBlock = 0 }
          else { $text .= $rest; $rest = '' }
        } elsif ($rest =~ s/^.*?(\/\/.*)$//) { $text .= $1 }
        elsif ($rest =~ s/^.*?\/\*//) { $inBlock = 1 }
        else { $rest = '' }
      }
    }
    next if $text eq '';
    my @hits;
    push @hits, "a date ($1)" while $text =~ /($date)/g;
    push @hits, "a commit hash ($1)" while $text =~ /($hash)/g;
    push @hits, "an issue reference ($1)" while $text =~ /($issue)/g;
    next unless @hits;
    next if grep { $_->[0] eq $rel && index($line, $_->[1]) >= 0 } @allow;
    chomp $line;
    $line =~ s/^\s+//;
    print "$rel:$.: " . join(', ', @hits) . ": $line\n";
    $problems++;
  }
}
if ($problems) {
  print "$problems lines hold history; say why the code or the tool is as it is instead (git "
    . "keeps the history), or, for a version a source must name, add the line to the allow-list\n";
  exit 1;
}
exit 0;
