/PROG  CTC01_PLAN
/ATTR
OWNER		= MNEDITOR;
COMMENT		= "scanplan";
PROG_SIZE	= 0;
CREATE		= DATE 00-01-01  TIME 00:00:00;
MODIFIED	= DATE 00-01-01  TIME 00:00:00;
FILE_NAME	= ;
VERSION		= 0;
LINE_COUNT	= 53;
MEMORY_SIZE	= 0;
PROTECT		= READ_WRITE;
TCD:  STACK_SIZE	= 0,
      TASK_PRIORITY	= 50,
      TIME_SLICE	= 0,
      BUSY_LAMP_OFF	= 0,
      ABORT_REQUEST	= 0,
      PAUSE_REQUEST	= 0;
DEFAULT_GROUP	= 1,*,*,*,*;
CONTROL_CODE	= 00000000 00000000;
/MN
   1:  !scanplan ctc01_plan: 3 views ;
   2:  !views left out: 1 ;
   3:  !UFRAME 1: X 1000.0 Y 0.0 Z 0.0 ;
   4:  !UFRAME 1: W 0.00 P 0.00 R 30.00 ;
   5:  !UTOOL 1: X 0.0 Y 0.0 Z 150.0 ;
   6:  !UTOOL 1: W 0.00 P 0.00 R 0.00 ;
   7:  !PAYLOAD 1: 3.20 kg ;
   8:  UFRAME_NUM=1 ;
   9:  UTOOL_NUM=1 ;
  10:  PAYLOAD[1] ;
  11:  DO[3]=OFF ;
  12:J P[1:HOME] 20% FINE ;
  13:J P[2:APPROACH4] 20% FINE ;
  14:  !view 4 (1 of 3) ;
  15:J P[3:VIEW4] 5% FINE ;
  16:  WAIT .20(sec) ;
  17:  GO[9]=4 ;
  18:  DO[3]=ON ;
  19:  $WAITTMOUT=1000 ;
  20:  WAIT DI[4]=ON TIMEOUT,LBL[90] ;
  21:  DO[3]=OFF ;
  22:  WAIT DI[4]=OFF TIMEOUT,LBL[91] ;
  23:J P[2:APPROACH4] 5% FINE ;
  24:J P[4:VIA1] 20% FINE ;
  25:  !view 2 (2 of 3) ;
  26:J P[5:VIEW2] 20% FINE ;
  27:  WAIT .20(sec) ;
  28:  GO[9]=2 ;
  29:  DO[3]=ON ;
  30:  $WAITTMOUT=1000 ;
  31:  WAIT DI[4]=ON TIMEOUT,LBL[90] ;
  32:  DO[3]=OFF ;
  33:  WAIT DI[4]=OFF TIMEOUT,LBL[91] ;
  34:  !view 7 (3 of 3) ;
  35:J P[6:VIEW7] 20% FINE ;
  36:  WAIT .20(sec) ;
  37:  GO[9]=7 ;
  38:  DO[3]=ON ;
  39:  $WAITTMOUT=1000 ;
  40:  WAIT DI[4]=ON TIMEOUT,LBL[90] ;
  41:  DO[3]=OFF ;
  42:  WAIT DI[4]=OFF TIMEOUT,LBL[91] ;
  43:J P[1:HOME] 20% FINE ;
  44:  JMP LBL[99] ;
  45:  LBL[90] ;
  46:  DO[3]=OFF ;
  47:  MESSAGE[NO SCAN ACKNOWLEDGE] ;
  48:  ABORT ;
  49:  LBL[91] ;
  50:  DO[3]=OFF ;
  51:  MESSAGE[SCAN ACKNOWLEDGE STUCK] ;
  52:  ABORT ;
  53:  LBL[99] ;
/POS
P[1:"HOME"]{
   GP1:
	UF : 1, UT : 1,	
	J1=     0.000 deg,	J2=   -17.189 deg,	J3=    11.459 deg,
	J4=     0.000 deg,	J5=    34.377 deg,	J6=     0.000 deg,
	E1=     0.000 deg
};
P[2:"APPROACH4"]{
   GP1:
	UF : 1, UT : 1,	
	J1=     5.730 deg,	J2=     5.730 deg,	J3=   -11.459 deg,
	J4=    22.918 deg,	J5=    28.648 deg,	J6=    34.377 deg,
	E1=     0.000 deg
};
P[3:"VIEW4"]{
   GP1:
	UF : 1, UT : 1,	
	J1=     5.730 deg,	J2=    11.459 deg,	J3=   -17.189 deg,
	J4=    22.918 deg,	J5=    28.648 deg,	J6=    34.377 deg,
	E1=     0.000 deg
};
P[4:"VIA1"]{
   GP1:
	UF : 1, UT : 1,	
	J1=    -5.730 deg,	J2=   -11.459 deg,	J3=     5.730 deg,
	J4=   -28.648 deg,	J5=    40.107 deg,	J6=    57.296 deg,
	E1=    45.837 deg
};
P[5:"VIEW2"]{
   GP1:
	UF : 1, UT : 1,	
	J1=   -11.459 deg,	J2=    22.918 deg,	J3=     5.730 deg,
	J4=   -57.296 deg,	J5=    45.837 deg,	J6=   114.592 deg,
	E1=    90.000 deg
};
P[6:"VIEW7"]{
   GP1:
	UF : 1, UT : 1,	
	J1=    28.648 deg,	J2=    -5.730 deg,	J3=    17.189 deg,
	J4=    11.459 deg,	J5=   -34.377 deg,	J6=   -85.944 deg,
	E1=     0.000 deg
};
/END
